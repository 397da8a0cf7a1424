#!/usr/bin/python3
"""Checks rendered PNGs: each exists, decodes, has the expected size and is not blank.

    check_pictures.py --size W,H [--regions NAME.png,NAME.png...] [--no-curves NAME.png,...] FILE.png...

Not blank: at least 5% of the pixels differ from the background (the corner colour), there are
more than 50 distinct colours, and some near-black pixels (the curves) are drawn. The pictures
named in --regions (file names, coloured by region) must also show at least 4 clearly different hues;
those named in --no-curves (outputs whose curves are written beside them) need no near-black pixels.
Standard library only (PNG decoded with zlib). Exit 0 when all pass, 1 otherwise.
"""
import colorsys
import struct
import sys
import zlib


def decode_png(path):
    """Returns (width, height, rows) with rows a list of lists of (r, g, b) tuples."""
    with open(path, "rb") as f:
        data = f.read()
    if data[:8] != b"\x89PNG\r\n\x1a\n":
        raise ValueError("not a PNG file")
    pos = 8
    idat = b""
    header = None
    while pos < len(data):
        (length,) = struct.unpack(">I", data[pos:pos + 4])
        kind = data[pos + 4:pos + 8]
        body = data[pos + 8:pos + 8 + length]
        (crc,) = struct.unpack(">I", data[pos + 8 + length:pos + 12 + length])
        if zlib.crc32(kind + body) & 0xFFFFFFFF != crc:
            raise ValueError("bad CRC in chunk %r" % kind)
        if kind == b"IHDR":
            header = struct.unpack(">IIBBBBB", body)
        elif kind == b"IDAT":
            idat += body
        elif kind == b"IEND":
            break
        pos += 12 + length
    if header is None:
        raise ValueError("no IHDR chunk")
    width, height, depth, colour_type, _, _, interlace = header
    channels = {0: 1, 2: 3, 4: 2, 6: 4}.get(colour_type)
    if depth != 8 or channels is None or interlace != 0:
        raise ValueError("unsupported PNG (depth %d, colour type %d, interlace %d)"
                         % (depth, colour_type, interlace))
    raw = zlib.decompress(idat)
    stride = width * channels
    if len(raw) != height * (stride + 1):
        raise ValueError("image data has %d bytes, expected %d" % (len(raw), height * (stride + 1)))
    rows = []
    previous = bytearray(stride)
    for y in range(height):
        start = y * (stride + 1)
        kind = raw[start]
        line = bytearray(raw[start + 1:start + 1 + stride])
        bpp = channels
        if kind == 1:
            for i in range(bpp, stride):
                line[i] = (line[i] + line[i - bpp]) & 0xFF
        elif kind == 2:
            for i in range(stride):
                line[i] = (line[i] + previous[i]) & 0xFF
        elif kind == 3:
            for i in range(stride):
                left = line[i - bpp] if i >= bpp else 0
                line[i] = (line[i] + ((left + previous[i]) >> 1)) & 0xFF
        elif kind == 4:
            for i in range(stride):
                a = line[i - bpp] if i >= bpp else 0
                b = previous[i]
                c = previous[i - bpp] if i >= bpp else 0
                p = a + b - c
                pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
                pred = a if pa <= pb and pa <= pc else (b if pb <= pc else c)
                line[i] = (line[i] + pred) & 0xFF
        elif kind != 0:
            raise ValueError("bad filter type %d in row %d" % (kind, y))
        previous = line
        if channels >= 3:
            rows.append([tuple(line[i:i + 3]) for i in range(0, stride, channels)])
        else:
            rows.append([(line[i],) * 3 for i in range(0, stride, channels)])
    return width, height, rows


def check(path, size, regions, curves=True):
    problems = []
    try:
        width, height, rows = decode_png(path)
    except (OSError, ValueError, zlib.error) as error:
        return ["%s: %s" % (path, error)]
    if (width, height) != size:
        problems.append("size %dx%d, expected %dx%d" % (width, height, size[0], size[1]))
    background = rows[0][0]
    pixels = [p for row in rows for p in row]
    foreground = [p for p in pixels if max(abs(a - b) for a, b in zip(p, background)) > 16]
    fraction = len(foreground) / len(pixels)
    colours = len(set(pixels))
    dark = sum(1 for p in pixels if max(p) < 70) / len(pixels)
    summary = "%.1f%% foreground, %d colours, %.2f%% curve pixels" % (
        100 * fraction, colours, 100 * dark)
    if fraction < 0.05:
        problems.append("blank: only %.1f%% of the pixels differ from the background" %
                        (100 * fraction))
    if colours <= 50:
        problems.append("only %d distinct colours" % colours)
    if curves and dark < 0.001:
        problems.append("no curves drawn (%.3f%% near-black pixels)" % (100 * dark))
    if regions:
        bins = [0] * 12
        for r, g, b in foreground:
            h, s, v = colorsys.rgb_to_hsv(r / 255, g / 255, b / 255)
            if s > 0.3 and v > 0.2:
                bins[int(h * 12) % 12] += 1
        hues = sum(1 for n in bins if n > 0.01 * len(foreground))
        summary += ", %d hues" % hues
        if hues < 4:
            problems.append("regions not coloured: %d hue bins hold over 1%% of the shape (%s)"
                            % (hues, bins))
    print("%s: %dx%d, %s%s" % (path, width, height, summary,
                               "" if not problems else " -- FAILED"))
    return ["%s: %s" % (path, p) for p in problems]


def main():
    args = sys.argv[1:]
    size, regions, no_curves, files = None, set(), set(), []
    i = 0
    while i < len(args):
        if args[i] == "--size":
            size = tuple(int(v) for v in args[i + 1].split(","))
            i += 2
        elif args[i] == "--regions":
            regions.update(args[i + 1].split(","))
            i += 2
        elif args[i] == "--no-curves":
            no_curves.update(args[i + 1].split(","))
            i += 2
        else:
            files.append(args[i])
            i += 1
    if size is None or not files:
        sys.stderr.write(__doc__)
        return 2
    problems = []
    for path in files:
        name = path.rsplit("/", 1)[-1]
        problems += check(path, size, name in regions, name not in no_curves)
    for p in problems:
        print("FAILED: " + p)
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
