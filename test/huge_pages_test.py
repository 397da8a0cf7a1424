#!/usr/bin/env python3
"""The command's restart with huge pages for its heap (src/cli/main.cpp, restart_with_huge_pages).

Watched from outside while it runs (/proc/<pid>): the restarted command's environment block
holds MESHFIT_GLIBC_TUNABLES_BEFORE, the caller's GLIBC_TUNABLES kept aside ("=" and the value, or
empty when there was none), and its heap lies partly in huge pages (AnonHugePages in
smaps_rollup). Three runs of `meshfit fit` on the example (3000 smoothing iterations, about a
second, so that the poll sees the running command):
  - with GLIBC_TUNABLES=glibc.malloc.arena_max=4: restarted, that value kept aside, huge pages;
  - without GLIBC_TUNABLES: restarted, nothing kept aside, huge pages;
  - with glibc.malloc.hugetlb=0 set by the caller: not restarted (the caller's choice stands), and
    where the kernel gives huge pages only on request ("[madvise]"), none.
Each run must also complete (exit 0) and write its output. Exit 77 (skipped) when the kernel has
transparent huge pages off ("[never]"), where the command does not restart. (What the restarted
command puts back into its environment for what it runs is not seen from outside: glibc rewrites
the environment block in place.)
"""
import argparse
import os
import subprocess
import sys
import tempfile
import time

ap = argparse.ArgumentParser()
ap.add_argument("--meshfit", required=True)
ap.add_argument("--data", required=True)
a = ap.parse_args()

try:
    with open("/sys/kernel/mm/transparent_hugepage/enabled") as f:
        thp = f.read()
        if "[never]" in thp:
            print("SKIPPED: transparent huge pages are off on this machine")
            sys.exit(77)
except OSError:
    print("SKIPPED: no /sys/kernel/mm/transparent_hugepage/enabled")
    sys.exit(77)

MARK = "MESHFIT_GLIBC_TUNABLES_BEFORE"


def run(tunables):
    """Runs the fit with GLIBC_TUNABLES = tunables (None: unset); returns the value kept aside
    (None when the command never showed the mark), the most huge-page memory seen (kB), the exit
    status and whether the output was written."""
    env = dict(os.environ)
    env.pop("GLIBC_TUNABLES", None)
    env.pop(MARK, None)
    if tunables is not None:
        env["GLIBC_TUNABLES"] = tunables
    with tempfile.TemporaryDirectory() as work:
        out = os.path.join(work, "out.off")
        p = subprocess.Popen([a.meshfit, "fit", "--template", os.path.join(a.data, "template.off"),
                              "--curves", os.path.join(a.data, "curves.polylines.txt"),
                              "--correspondences", os.path.join(a.data, "pairs.txt"),
                              "--output", out, "--quiet", "--iterations", "3000"], env=env)
        kept, huge = None, 0
        while p.poll() is None:
            try:
                with open("/proc/%d/environ" % p.pid, "rb") as f:
                    entries = [e.decode() for e in f.read().split(b"\0") if e]
                with open("/proc/%d/smaps_rollup" % p.pid) as f:
                    for line in f:
                        if line.startswith("AnonHugePages:"):
                            huge = max(huge, int(line.split()[1]))
            except (OSError, ValueError):
                break
            for e in entries:
                if e.startswith(MARK + "="):
                    kept = e[len(MARK) + 1:]
            time.sleep(0.001)
        status = p.wait()
        written = os.path.isfile(out) and os.path.getsize(out) > 0
    return kept, huge, status, written


failures = []


def check(what, ok):
    print(("ok   " if ok else "FAIL ") + what)
    if not ok:
        failures.append(what)


kept, huge, status, written = run("glibc.malloc.arena_max=4")
check("with the caller's tunable: exit 0 and an output", status == 0 and written)
check("with the caller's tunable: restarted, the value kept aside (%r)" % kept, kept == "=glibc.malloc.arena_max=4")
check("with the caller's tunable: heap in huge pages (%d kB)" % huge, huge > 0)

kept, huge, status, written = run(None)
check("without GLIBC_TUNABLES: exit 0 and an output", status == 0 and written)
check("without GLIBC_TUNABLES: restarted, nothing kept aside (%r)" % kept, kept == "")
check("without GLIBC_TUNABLES: heap in huge pages (%d kB)" % huge, huge > 0)

kept, huge, status, written = run("glibc.malloc.hugetlb=0")
check("with hugetlb=0 from the caller: exit 0 and an output", status == 0 and written)
check("with hugetlb=0 from the caller: not restarted (%r)" % kept, kept is None)
if "[madvise]" in thp:
    check("with hugetlb=0 from the caller: no huge pages (%d kB)" % huge, huge == 0)

sys.exit(1 if failures else 0)
