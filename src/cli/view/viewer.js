// meshfit view: the page's code. `meshfit view` writes the data (a JSON block #mf-data and the
// meshes as base64 little-endian typed arrays in <script type="application/octet-stream">
// elements) before this script; three.js r111 and its OrbitControls are inlined before it too.
(function () {
  'use strict';
  const t0 = performance.now();
  const data = JSON.parse(document.getElementById('mf-data').textContent);
  const params = new URLSearchParams(location.search);
  // Above this many faces a mesh is shown decimated (vertex clustering); the page says so.
  const maxDisplayFaces = Number(params.get('maxfaces')) || 1500000;
  const api = { ready: false, errors: [], notices: [], timings: {} };
  const mark = (what) => { api.timings[what] = Math.round(performance.now() - t0); };
  window.meshfitView = api;
  window.addEventListener('error', (e) => api.errors.push(String(e.message)));

  // ---- data ------------------------------------------------------------------------------------
  const base64 = new Uint8Array(256);
  'ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/'.split('').forEach((c, i) => { base64[c.charCodeAt(0)] = i; });
  function bytes(id) {
    const s = document.getElementById(id).textContent.trim();
    const pad = s.endsWith('==') ? 2 : s.endsWith('=') ? 1 : 0;
    const out = new Uint8Array((s.length / 4) * 3 - pad);
    const n = out.length;
    let j = 0;
    for (let i = 0; i < s.length; i += 4) {
      const v = (base64[s.charCodeAt(i)] << 18) | (base64[s.charCodeAt(i + 1)] << 12) |
                (base64[s.charCodeAt(i + 2)] << 6) | base64[s.charCodeAt(i + 3)];
      out[j++] = v >> 16;
      if (j < n) out[j++] = (v >> 8) & 255;
      if (j < n) out[j++] = v & 255;
    }
    return out.buffer;
  }
  function decodeMesh(m) {
    return {
      name: m.name, vertices: m.vertices, faces: m.faces, regions: m.regions || 0,
      positions: new Float32Array(bytes(m.positions)),
      triangles: new Uint32Array(bytes(m.triangles)),
      patch: m.patch ? new Int32Array(bytes(m.patch)) : null,
      curves: m.curves ? new Uint32Array(bytes(m.curves)) : null,
      report: m.report, reportName: m.report_name,
      original: null, // display vertex -> file vertex, when decimated
    };
  }
  const origin = data.origin;
  const scale = data.scale || 1; // file coordinates -> drawing: (x - origin) * scale
  let template = decodeMesh(data.template);
  let results = data.results.map(decodeMesh);
  const network = {
    name: data.network.name,
    points: new Float64Array(bytes(data.network.points)), // exact coordinates, as saved
    segments: new Uint32Array(bytes(data.network.segment_ends)),
  };
  const networkCount = network.points.length / 3;
  network.display = new Float32Array(3 * networkCount);
  for (let i = 0; i < 3 * networkCount; ++i) network.display[i] = (network.points[i] - origin[i % 3]) * scale;

  // ---- display decimation: vertex clustering on a grid -----------------------------------------
  // A mesh above `maxDisplayFaces` is shown decimated. When a full frame takes longer than 40 ms
  // (software rendering, a weak GPU), the meshes in view are drawn decimated while the view turns,
  // as many faces as render in about 25 ms, and in full when it stops. The page says both.
  const orbitFaces = Number(params.get('orbitfaces')) || 300000;
  function cluster(mesh, budget) {
    const P = mesh.positions, T = mesh.triangles;
    const lo = [Infinity, Infinity, Infinity], hi = [-Infinity, -Infinity, -Infinity];
    for (let i = 0; i < P.length; ++i) { const k = i % 3; lo[k] = Math.min(lo[k], P[i]); hi[k] = Math.max(hi[k], P[i]); }
    const size = Math.max(hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]) || 1;
    // About 2π res² faces on a closed surface in a res³ grid; finer or coarser surfaces retry.
    let res = Math.max(4, Math.floor(Math.sqrt(budget / (2 * Math.PI))));
    for (let attempt = 0; ; ++attempt, res = Math.max(2, Math.floor(res * 0.8))) {
      const cell = new Map(), sum = [], first = [];
      const map = new Int32Array(P.length / 3);
      const index = (x, k) => Math.min(res - 1, Math.floor((x - lo[k]) / size * res));
      for (let v = 0; v < map.length; ++v) {
        const key = (index(P[3 * v], 0) * res + index(P[3 * v + 1], 1)) * res + index(P[3 * v + 2], 2);
        let c = cell.get(key);
        if (c === undefined) { c = first.length; cell.set(key, c); first.push(v); sum.push(0, 0, 0, 0); }
        map[v] = c;
        sum[4 * c] += P[3 * v]; sum[4 * c + 1] += P[3 * v + 1]; sum[4 * c + 2] += P[3 * v + 2]; sum[4 * c + 3] += 1;
      }
      const tris = [], patch = [];
      for (let f = 0; f < T.length / 3; ++f) {
        const a = map[T[3 * f]], b = map[T[3 * f + 1]], c = map[T[3 * f + 2]];
        if (a === b || b === c || a === c) continue;
        tris.push(a, b, c);
        if (mesh.patch) patch.push(mesh.patch[f]);
      }
      if (tris.length / 3 > budget && attempt < 5) continue;
      const pos = new Float32Array(3 * first.length);
      for (let c = 0; c < first.length; ++c) for (let k = 0; k < 3; ++k) pos[3 * c + k] = sum[4 * c + k] / sum[4 * c + 3];
      let curves = null;
      if (mesh.curves) {
        const e = [];
        for (let i = 0; i < mesh.curves.length; i += 2) {
          const a = map[mesh.curves[i]], b = map[mesh.curves[i + 1]];
          if (a !== b) e.push(a, b);
        }
        curves = new Uint32Array(e);
      }
      return Object.assign({}, mesh, { positions: pos, triangles: new Uint32Array(tris), patch: mesh.patch ? new Int32Array(patch) : null,
                                       curves: curves, original: Int32Array.from(first) });
    }
  }
  const faceCount = (mesh) => (mesh.triangles.length / 3).toLocaleString('en');
  const later = []; // notices, shown once the panel is built
  function decimateForDisplay(mesh) {
    if (mesh.faces <= maxDisplayFaces) return mesh;
    const d = cluster(mesh, maxDisplayFaces);
    later.push(mesh.name + ': shown decimated (vertex clustering), ' + faceCount(d) + ' of ' +
                     mesh.faces.toLocaleString('en') + ' faces; the file is unchanged' +
                     (mesh === template ? ', and picks snap to the nearest kept vertex' : ''));
    return d;
  }
  mark('decoded');
  template = decimateForDisplay(template);
  results = results.map(decimateForDisplay);

  // ---- scene -----------------------------------------------------------------------------------
  const container = document.getElementById('view');
  const renderer = new THREE.WebGLRenderer({ antialias: true, preserveDrawingBuffer: true });
  renderer.setPixelRatio(window.devicePixelRatio || 1);
  container.appendChild(renderer.domElement);
  const scene = new THREE.Scene();
  scene.background = new THREE.Color(0xffffff);
  const camera = new THREE.PerspectiveCamera(35, 1, 1e-3, 1e3);
  scene.add(camera);
  scene.add(new THREE.HemisphereLight(0xffffff, 0x707070, 0.55));
  const light = new THREE.DirectionalLight(0xffffff, 0.55);
  light.position.set(0.3, 0.6, 1);
  camera.add(light);
  const controls = new THREE.OrbitControls(camera, renderer.domElement);
  controls.addEventListener('change', render);
  let turning = false; // while the user turns the view, large meshes may be drawn decimated
  let fullFrameMs = 0;
  function useProxies() {
    if (fullFrameMs < 40) return false;
    for (const l of [templateLayer].concat(resultLayers)) {
      const faces = l.mesh.triangles.length / 3;
      if (l.proxy || !l.group.visible || faces < 40000) continue;
      const budget = Math.max(20000, Math.min(orbitFaces, faces * 25 / fullFrameMs));
      const coarse = cluster(l.mesh, budget);
      l.proxy = surface(coarse, l.flat).surface;
      l.group.add(l.proxy);
      notice(l.mesh.name + ': drawn decimated to ' + faceCount(coarse) + ' faces while the view turns (a full frame took ' +
             Math.round(fullFrameMs) + ' ms), in full when it stops');
    }
    return true;
  }
  controls.addEventListener('start', () => { turning = useProxies(); update(); });
  controls.addEventListener('end', () => { turning = false; update(); timeFrame(); });

  function regionColour(r) {
    // Golden-angle hues, bright enough that black curve edges stand out on every region.
    const c = new THREE.Color().setHSL(((r * 0.381966) % 1 + 1) % 1, 0.65, 0.58);
    return [Math.round(c.r * 255), Math.round(c.g * 255), Math.round(c.b * 255)];
  }
  function surface(mesh, flat) {
    const P = mesh.positions, T = mesh.triangles, m = T.length / 3;
    const pos = new Float32Array(9 * m), col = new Uint8Array(9 * m);
    const cache = new Map();
    for (let f = 0; f < m; ++f) {
      let c = flat;
      if (mesh.patch) {
        const r = mesh.patch[f];
        c = cache.get(r);
        if (!c) { c = regionColour(r); cache.set(r, c); }
      }
      for (let k = 0; k < 3; ++k) {
        const v = T[3 * f + k], o = 9 * f + 3 * k;
        pos[o] = P[3 * v]; pos[o + 1] = P[3 * v + 1]; pos[o + 2] = P[3 * v + 2];
        col[o] = c[0]; col[o + 1] = c[1]; col[o + 2] = c[2];
      }
    }
    const g = new THREE.BufferGeometry();
    g.setAttribute('position', new THREE.BufferAttribute(pos, 3));
    g.setAttribute('color', new THREE.BufferAttribute(col, 3, true));
    g.computeBoundingSphere();
    const material = new THREE.MeshPhongMaterial({
      vertexColors: THREE.VertexColors, flatShading: true, side: THREE.DoubleSide, shininess: 10,
      polygonOffset: true, polygonOffsetFactor: 1, polygonOffsetUnits: 1,
    });
    const surfaceMesh = new THREE.Mesh(g, material);
    const wire = new THREE.Mesh(g, new THREE.MeshBasicMaterial({ color: 0x000000, wireframe: true, transparent: true, opacity: 0.18 }));
    wire.visible = false;
    return { surface: surfaceMesh, wire: wire };
  }
  function lines(P, ends, colour) {
    const pos = new Float32Array(3 * ends.length);
    for (let i = 0; i < ends.length; ++i) for (let k = 0; k < 3; ++k) pos[3 * i + k] = P[3 * ends[i] + k];
    const g = new THREE.BufferGeometry();
    g.setAttribute('position', new THREE.BufferAttribute(pos, 3));
    return new THREE.LineSegments(g, new THREE.LineBasicMaterial({ color: colour }));
  }
  function meshLayer(mesh, flat) {
    const group = new THREE.Group();
    const s = surface(mesh, flat);
    group.add(s.surface, s.wire);
    const layer = { mesh: mesh, group: group, surface: s.surface, wire: s.wire, curves: null, proxy: null, flat: flat };
    if (mesh.curves) { layer.curves = lines(mesh.positions, mesh.curves, 0x000000); group.add(layer.curves); }
    return layer;
  }

  const templateGroup = new THREE.Group();      // moved aside in the side-by-side layout
  const targetGroup = new THREE.Group();        // the network and the results, in place
  scene.add(templateGroup, targetGroup);
  const templateLayer = meshLayer(template, [200, 200, 206]);
  templateGroup.add(templateLayer.group);
  const networkLines = lines(network.display, network.segments, 0xc0143c);
  const pointsGeometry = new THREE.BufferGeometry();
  pointsGeometry.setAttribute('position', new THREE.BufferAttribute(network.display, 3));
  const networkPoints = new THREE.Points(pointsGeometry, new THREE.PointsMaterial({ color: 0x80102a, size: 4, sizeAttenuation: false }));
  targetGroup.add(networkLines, networkPoints);
  const resultLayers = results.map((r) => { const l = meshLayer(r, [200, 200, 206]); l.group.visible = false; targetGroup.add(l.group); return l; });
  const markerGroup = new THREE.Group();
  scene.add(markerGroup);
  mark('geometry');

  function box(P) {
    const b = new THREE.Box3();
    for (let i = 0; i < P.length; i += 3) b.expandByPoint(new THREE.Vector3(P[i], P[i + 1], P[i + 2]));
    return b;
  }
  const templateBox = box(template.positions), networkBox = box(network.display);
  function applyLayout(layout) {
    if (layout === 'side') {
      const tc = templateBox.getCenter(new THREE.Vector3()), nc = networkBox.getCenter(new THREE.Vector3());
      const tw = templateBox.max.x - templateBox.min.x, nw = networkBox.max.x - networkBox.min.x;
      const gap = 0.15 * Math.max(tw, nw, templateBox.getSize(new THREE.Vector3()).length() * 0.3);
      templateGroup.position.set(nc.x - nw / 2 - gap - tw / 2 - tc.x, nc.y - tc.y, nc.z - tc.z);
    } else {
      templateGroup.position.set(0, 0, 0);
    }
    templateGroup.updateMatrixWorld(true);
  }
  function resetCamera() {
    const b = new THREE.Box3().setFromObject(templateLayer.surface).union(networkBox);
    const sphere = b.getBoundingSphere(new THREE.Sphere());
    const r = sphere.radius || 1;
    const dir = new THREE.Vector3(0.15, 0.35, 1).normalize();
    const fov = camera.fov * Math.PI / 180;
    const aspect = camera.aspect;
    const dist = r / Math.sin(Math.min(fov, 2 * Math.atan(Math.tan(fov / 2) * aspect)) / 2) * 0.9;
    controls.target.copy(sphere.center);
    // The bounding sphere leaves a wide scene small: move in until the box's corners fill 90%.
    const corners = [];
    for (let k = 0; k < 8; ++k) corners.push(new THREE.Vector3(k & 1 ? b.max.x : b.min.x, k & 2 ? b.max.y : b.min.y, k & 4 ? b.max.z : b.min.z));
    let d = dist;
    for (let round = 0; round < 3; ++round) {
      camera.position.copy(sphere.center).addScaledVector(dir, d);
      camera.near = d / 100; camera.far = d * 10;
      camera.updateProjectionMatrix();
      camera.lookAt(sphere.center);
      camera.updateMatrixWorld(true);
      const extent = Math.max(...corners.map((c) => { const q = c.clone().project(camera); return Math.max(Math.abs(q.x), Math.abs(q.y)); }));
      d = Math.min(dist, d * Math.max(0.2, extent / 0.9));
    }
    camera.position.copy(sphere.center).addScaledVector(dir, d);
    camera.near = d / 100; camera.far = d * 10;
    camera.updateProjectionMatrix();
    controls.update();
  }
  function resize() {
    const w = container.clientWidth, h = container.clientHeight;
    renderer.setSize(w, h);
    camera.aspect = w / h;
    camera.updateProjectionMatrix();
    render();
  }

  // ---- layers panel ----------------------------------------------------------------------------
  const state = { template: true, network: true, networkVertices: true, pairs: true, curves: true, wireframe: false,
                  result: results.length - 1, layout: 'side' };
  function checkbox(parent, key, text) {
    const label = document.createElement('label');
    const input = document.createElement('input');
    input.type = 'checkbox'; input.checked = state[key]; input.dataset.layer = key;
    input.addEventListener('change', () => { state[key] = input.checked; update(); });
    label.append(input, ' ' + text);
    parent.append(label);
  }
  const layersDiv = document.getElementById('layers');
  checkbox(layersDiv, 'template', 'template ' + template.name + ' (' + data.template.faces.toLocaleString('en') + ' faces)');
  checkbox(layersDiv, 'network', 'network ' + network.name + ' (' + networkCount + ' vertices, ' + data.network.segments + ' segments)');
  checkbox(layersDiv, 'networkVertices', 'network vertices');
  checkbox(layersDiv, 'pairs', 'pair markers');
  const radios = [['none', -1]].concat(results.map((r, k) => [r.name + ' (' + data.results[k].faces.toLocaleString('en') + ' faces' +
                                         (r.regions ? ', ' + r.regions + ' regions' : '') + ')', k]));
  for (const [text, k] of radios) {
    const label = document.createElement('label');
    const input = document.createElement('input');
    input.type = 'radio'; input.name = 'result'; input.checked = state.result === k; input.dataset.result = k;
    input.addEventListener('change', () => { if (input.checked) { state.result = k; update(); } });
    label.append(input, ' ' + (k < 0 ? 'no result' : 'result: ' + text));
    layersDiv.append(label);
  }
  checkbox(layersDiv, 'curves', 'curve edges of the result');
  checkbox(layersDiv, 'wireframe', 'wireframe');
  const layoutSelect = document.getElementById('layout');
  layoutSelect.addEventListener('change', () => { state.layout = layoutSelect.value; update(); resetCamera(); });
  document.getElementById('reset-camera').addEventListener('click', resetCamera);

  function update() {
    applyLayout(state.layout);
    templateLayer.group.visible = state.template;
    networkLines.visible = state.network;
    networkPoints.visible = state.network && state.networkVertices;
    resultLayers.forEach((l, k) => {
      l.group.visible = k === state.result;
      if (l.curves) l.curves.visible = state.curves;
    });
    for (const l of [templateLayer].concat(resultLayers)) {
      l.surface.visible = !(turning && l.proxy);
      l.wire.visible = state.wireframe && !(turning && l.proxy);
      if (l.proxy) l.proxy.visible = turning;
    }
    markerGroup.visible = state.pairs;
    for (const input of layersDiv.querySelectorAll('input[data-layer]')) input.checked = state[input.dataset.layer];
    for (const input of layersDiv.querySelectorAll('input[data-result]')) input.checked = Number(input.dataset.result) === state.result;
    layoutSelect.value = state.layout;
    rebuildMarkers();
    render();
  }

  // ---- pairs -----------------------------------------------------------------------------------
  let pairs = data.pairs.map((p) => ({ t: p[0], n: p[1] }));
  let pending = { t: null, n: null };
  const markerTextures = new Map();
  function markerTexture(text, fill) {
    const key = text + fill;
    if (markerTextures.has(key)) return markerTextures.get(key);
    const c = document.createElement('canvas');
    c.width = c.height = 64;
    const g = c.getContext('2d');
    g.fillStyle = fill; g.strokeStyle = '#000'; g.lineWidth = 4;
    g.beginPath(); g.arc(32, 32, 28, 0, 2 * Math.PI); g.fill(); g.stroke();
    g.fillStyle = '#000'; g.font = 'bold ' + (text.length > 2 ? 24 : 32) + 'px sans-serif';
    g.textAlign = 'center'; g.textBaseline = 'middle';
    g.fillText(text, 32, 34);
    const t = new THREE.CanvasTexture(c);
    markerTextures.set(key, t);
    return t;
  }
  function templatePosition(i, target) {
    // A template vertex in world coordinates (decimated templates: its cluster's representative).
    let v = i;
    if (template.original) { v = nearestKept(i); }
    const P = template.positions;
    return target.set(P[3 * v], P[3 * v + 1], P[3 * v + 2]).applyMatrix4(templateGroup.matrixWorld);
  }
  function nearestKept(i) {
    // Only for decimated templates: the kept vertex whose original index is i, else the first.
    const o = template.original;
    for (let k = 0; k < o.length; ++k) if (o[k] === i) return k;
    return 0;
  }
  function networkPosition(v, target) {
    const P = network.display;
    return target.set(P[3 * v], P[3 * v + 1], P[3 * v + 2]).applyMatrix4(targetGroup.matrixWorld);
  }
  function marker(text, position, fill) {
    const s = new THREE.Sprite(new THREE.SpriteMaterial({ map: markerTexture(text, fill), sizeAttenuation: false, depthTest: false }));
    s.scale.set(0.028, 0.028, 1);
    s.position.copy(position);
    s.renderOrder = 10;
    markerGroup.add(s);
  }
  function rebuildMarkers() {
    while (markerGroup.children.length) markerGroup.remove(markerGroup.children[0]);
    const p = new THREE.Vector3();
    pairs.forEach((pair, k) => {
      const label = String(k + 1);
      if (state.template) marker(label, templatePosition(pair.t, p), '#ffd24a');
      if (state.network) marker(label, networkPosition(pair.n, p), '#ffd24a');
    });
    if (pending.t !== null) marker('?', templatePosition(pending.t, p), '#ff8c3a');
    if (pending.n !== null) marker('?', networkPosition(pending.n, p), '#ff8c3a');
  }
  function formatPoint(v) {
    const P = network.points;
    return [P[3 * v], P[3 * v + 1], P[3 * v + 2]].map(String).join(' ');
  }
  function addPair(t, n) {
    const replaced = pairs.filter((p) => p.t === t || p.n === n);
    if (replaced.length) api.lastNotice = 'replaced ' + replaced.map((p) => 'pair ' + (pairs.indexOf(p) + 1)).join(', ') + ' (same vertex)';
    pairs = pairs.filter((p) => p.t !== t && p.n !== n);
    pairs.push({ t: t, n: n });
    pending = { t: null, n: null };
    pairsChanged();
  }
  function pairsChanged() {
    const list = document.getElementById('pairs');
    list.textContent = '';
    pairs.forEach((pair, k) => {
      const li = document.createElement('li');
      const remove = document.createElement('button');
      remove.textContent = '✕'; remove.title = 'remove pair ' + (k + 1);
      remove.addEventListener('click', () => { pairs.splice(k, 1); pairsChanged(); });
      li.append(remove, 'template ' + pair.t + ' ↔ network ' + pair.n + ' ');
      const code = document.createElement('span');
      code.className = 'muted'; code.textContent = '(' + formatPoint(pair.n).split(' ').map((x) => Number(x).toPrecision(4)).join(', ') + ')';
      li.append(code);
      list.append(li);
    });
    const pend = document.getElementById('pending');
    pend.textContent = pending.t !== null ? 'template vertex ' + pending.t + ' chosen: now click a network vertex'
                     : pending.n !== null ? 'network vertex ' + pending.n + ' chosen: now click a template vertex' : '';
    if (api.lastNotice) { pend.textContent += (pend.textContent ? '; ' : '') + api.lastNotice; api.lastNotice = ''; }
    const warnings = document.getElementById('warnings');
    warnings.textContent = '';
    for (const w of pairWarnings()) {
      const d = document.createElement('div');
      d.className = 'warning'; d.textContent = w;
      warnings.append(d);
    }
    rebuildMarkers();
    render();
  }

  // Shape of a point set: eigenvalues of its covariance (closed form for symmetric 3x3).
  function spread(points) {
    const n = points.length, c = [0, 0, 0];
    for (const p of points) for (let k = 0; k < 3; ++k) c[k] += p[k] / n;
    const a = [0, 0, 0, 0, 0, 0]; // xx xy xz yy yz zz
    for (const p of points) {
      const x = p[0] - c[0], y = p[1] - c[1], z = p[2] - c[2];
      a[0] += x * x; a[1] += x * y; a[2] += x * z; a[3] += y * y; a[4] += y * z; a[5] += z * z;
    }
    const [xx, xy, xz, yy, yz, zz] = a;
    const p1 = xy * xy + xz * xz + yz * yz, q = (xx + yy + zz) / 3;
    let e;
    if (p1 === 0) e = [xx, yy, zz].sort((u, v) => v - u);
    else {
      const p2 = (xx - q) ** 2 + (yy - q) ** 2 + (zz - q) ** 2 + 2 * p1, p = Math.sqrt(p2 / 6);
      const b = [(xx - q) / p, xy / p, xz / p, (yy - q) / p, yz / p, (zz - q) / p];
      const det = b[0] * (b[3] * b[5] - b[4] * b[4]) - b[1] * (b[1] * b[5] - b[4] * b[2]) + b[2] * (b[1] * b[4] - b[3] * b[2]);
      const r = Math.max(-1, Math.min(1, det / 2)), phi = Math.acos(r) / 3;
      const e1 = q + 2 * p * Math.cos(phi), e3 = q + 2 * p * Math.cos(phi + 2 * Math.PI / 3);
      e = [e1, 3 * q - e1 - e3, e3];
    }
    // meshfit's own test of nearly coplanar pairs (rbf.cpp, nearly_coplanar): the rows
    // ((p - centroid) / bounding-box diagonal, 1), whose n x 4 matrix has the singular values
    // sqrt(n) and those of the centred points (the column of ones is orthogonal to them); the
    // smallest over the largest.
    let lo = [Infinity, Infinity, Infinity], hi = [-Infinity, -Infinity, -Infinity];
    for (const p of points) for (let k = 0; k < 3; ++k) lo[k] = Math.min(lo[k], p[k]), hi[k] = Math.max(hi[k], p[k]);
    const d2 = (hi[0] - lo[0]) ** 2 + (hi[1] - lo[1]) ** 2 + (hi[2] - lo[2]) ** 2;
    const sv = [n, ...e.map((x) => Math.max(0, x) / (d2 || 1))];
    const conditioning = Math.sqrt(Math.min(...sv) / Math.max(...sv));
    return { centre: c, flatness: Math.sqrt(Math.max(0, e[2]) / (e[0] || 1)), thinness: Math.sqrt(Math.max(0, e[1]) / (e[0] || 1)),
             conditioning: conditioning };
  }
  function det3(m) {
    return m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
           m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
  }
  // The least-squares affine map q ≈ A p + b of the pairs, centred: A = (PᵀP)⁻¹ PᵀQ, so the sign of
  // det A is the sign of det(PᵀQ) (PᵀP is positive definite when the template points span 3D).
  function affineDeterminant(P, Q) {
    const cp = spread(P).centre, cq = spread(Q).centre;
    const PtQ = [[0, 0, 0], [0, 0, 0], [0, 0, 0]], PtP = [[0, 0, 0], [0, 0, 0], [0, 0, 0]];
    for (let i = 0; i < P.length; ++i)
      for (let r = 0; r < 3; ++r)
        for (let c = 0; c < 3; ++c) {
          PtQ[r][c] += (P[i][r] - cp[r]) * (Q[i][c] - cq[c]);
          PtP[r][c] += (P[i][r] - cp[r]) * (P[i][c] - cp[c]);
        }
    return det3(PtQ) / det3(PtP);
  }
  function pairWarnings() {
    const w = [];
    const n = pairs.length;
    if (n < 4) w.push(n + (n === 1 ? ' pair' : ' pairs') + ': meshfit fit needs at least 4');
    if (n < 3) return w;
    const P = pairs.map((p) => { const q = templatePosition(p.t, new THREE.Vector3()).sub(templateGroup.position); return [q.x, q.y, q.z]; });
    const Q = pairs.map((p) => [network.points[3 * p.n], network.points[3 * p.n + 1], network.points[3 * p.n + 2]]);
    const sp = spread(P), sq = spread(Q);
    const flat = 1e-3;
    for (const [s, side] of [[sp, 'template'], [sq, 'network']])
      if (s.thinness < flat) w.push('the pairs\' ' + side + ' vertices are collinear: meshfit fit refuses them');
    if (sp.thinness >= flat && sq.thinness >= flat) {
      const thickness = (s) => ' (thickness ' + s.flatness.toExponential(1) + ' of their extent)';
      // As meshfit judges them (correspondence.cpp): network points on one plane to rounding with
      // template vertices not nearly coplanar (rbf_coplanarity_bound, 1e-2) are refused; template
      // vertices nearly coplanar get auxiliary pairs.
      const templateFlat = sp.conditioning < 1e-2, rounding = 1e-12;
      if (sq.flatness < flat && !templateFlat)
        w.push('the pairs\' network vertices are ' + (sq.flatness < rounding ? 'coplanar' : 'nearly coplanar') + thickness(sq) +
               ' but their template vertices are not: ' +
               (sq.flatness < rounding ? 'meshfit fit refuses them (the template would be flattened)'
                                       : 'the coarse level will nearly flatten the template') + '; add a pair off that plane');
      else if (templateFlat)
        w.push('the pairs\' template vertices are ' + (sp.flatness < flat ? 'coplanar' : 'nearly coplanar') + thickness(sp) +
               (sq.flatness < flat ? ', and so are their network vertices' : '') +
               ': meshfit adds auxiliary pairs off the plane; add a pair off it to decide the orientation yourself');
    }
    if (n >= 4 && sp.conditioning >= 1e-2 && sq.flatness >= flat) {
      const d = affineDeterminant(P, Q);
      api.determinant = d;
      if (d < 0) w.push('the pairs mirror the template: the best affine map from the template to the network has determinant ' +
                        d.toPrecision(3) + ' < 0 (a reflection): meshfit fit refuses such pairs in stage 1');
    } else api.determinant = null;
    return w;
  }
  function correspondencesText() {
    return '# template_vertex x y z (meshfit view)\n' + pairs.map((p) => p.t + ' ' + formatPoint(p.n) + '\n').join('');
  }
  document.getElementById('save').addEventListener('click', () => {
    const a = document.createElement('a');
    a.href = URL.createObjectURL(new Blob([correspondencesText()], { type: 'text/plain' }));
    a.download = data.pairs_name;
    document.body.append(a);
    a.click();
    a.remove();
  });
  document.getElementById('clear').addEventListener('click', () => { pairs = []; pending = { t: null, n: null }; pairsChanged(); });

  // ---- picking ---------------------------------------------------------------------------------
  const raycaster = new THREE.Raycaster();
  function ndc(x, y) {
    const r = renderer.domElement.getBoundingClientRect();
    return new THREE.Vector2(((x - r.left) / r.width) * 2 - 1, -((y - r.top) / r.height) * 2 + 1);
  }
  function pickTemplate(x, y) {
    if (!state.template) return null;
    raycaster.setFromCamera(ndc(x, y), camera);
    const hit = raycaster.intersectObject(templateLayer.surface)[0];
    if (!hit) return null;
    const T = template.triangles, f = hit.faceIndex;
    let best = null, bestD = Infinity;
    const p = new THREE.Vector3();
    for (let k = 0; k < 3; ++k) {
      const v = T[3 * f + k];
      const P = template.positions;
      const d = p.set(P[3 * v], P[3 * v + 1], P[3 * v + 2]).applyMatrix4(templateGroup.matrixWorld).distanceToSquared(hit.point);
      if (d < bestD) { bestD = d; best = v; }
    }
    return { vertex: template.original ? template.original[best] : best };
  }
  function pickNetwork(x, y, radius) {
    // The network vertex nearest to the click on the screen (the nearer to the eye on a tie).
    if (!state.network) return null;
    const r = renderer.domElement.getBoundingClientRect();
    const p = new THREE.Vector3();
    let best = null, bestD = radius * radius, bestZ = Infinity;
    for (let v = 0; v < networkCount; ++v) {
      networkPosition(v, p).project(camera);
      if (p.z < -1 || p.z > 1) continue;
      const sx = r.left + (p.x + 1) / 2 * r.width, sy = r.top + (1 - p.y) / 2 * r.height;
      const d = (sx - x) ** 2 + (sy - y) ** 2;
      if (d < bestD - 1 || (d <= bestD + 1 && p.z < bestZ)) { best = v; bestD = d; bestZ = p.z; }
    }
    return best === null ? null : { vertex: best };
  }
  function click(x, y) {
    if (!document.getElementById('picking').checked) return;
    const t = pickTemplate(x, y), n = pickNetwork(x, y, 14);
    // Where both are under the cursor (overlaid layout), the one the pending pair lacks wins.
    let kind = null;
    if (t && n) kind = pending.t !== null ? 'n' : 't';
    else if (t) kind = 't';
    else if (n) kind = 'n';
    if (!kind) return;
    if (kind === 't') pending.t = t.vertex; else pending.n = n.vertex;
    if (pending.t !== null && pending.n !== null) addPair(pending.t, pending.n);
    else pairsChanged();
  }
  let down = null;
  renderer.domElement.addEventListener('pointerdown', (e) => { down = { x: e.clientX, y: e.clientY }; });
  renderer.domElement.addEventListener('pointerup', (e) => {
    if (down && Math.abs(e.clientX - down.x) + Math.abs(e.clientY - down.y) < 5 && e.button === 0) click(e.clientX, e.clientY);
    down = null;
  });

  // ---- report ----------------------------------------------------------------------------------
  function showReports() {
    const div = document.getElementById('report');
    const files = document.getElementById('files');
    files.textContent = 'template ' + template.name + ', network ' + network.name + ', ' + data.pairs.length +
                        ' pairs given' + (results.length ? ', ' + results.length + ' result(s)' : '');
    if (!results.some((r) => r.report)) div.textContent = 'no report given (meshfit view --result R --result-report R.json)';
    results.forEach((r) => {
      if (!r.report) return;
      const h = document.createElement('div');
      h.innerHTML = '<b></b>';
      h.firstChild.textContent = r.reportName + ' (' + r.name + ')';
      div.append(h);
      let json = null;
      try { json = JSON.parse(r.report); } catch (e) { /* shown as text below */ }
      if (json) {
        const table = document.createElement('table');
        table.className = 'summary';
        const row = (k, v) => { const tr = table.insertRow(); tr.insertCell().textContent = k; tr.insertCell().textContent = v; };
        row('command', json.command);
        row('completed', String(json.completed) + (json.failure ? ': ' + json.failure : ''));
        if ('verified' in json) row('verified', String(json.verified));
        if (json.verification && json.verification.problems && json.verification.problems.length) row('problems', json.verification.problems.join('; '));
        if (json.counts) for (const k of ['correspondences', 'flips_found', 'segments', 'segments_embedded_by_walk', 'segments_embedded_by_fallback', 'segments_not_embedded', 'regions', 'iterations'])
          if (k in json.counts) row(k.replace(/_/g, ' '), json.counts[k]);
        if (json.quality) row('faces, vertices', json.quality.faces + ', ' + json.quality.vertices);
        if (json.quality && json.quality.minimum_angle_deg !== undefined) row('minimum angle', json.quality.minimum_angle_deg + '°');
        if (json.timings_s) row('time', Object.entries(json.timings_s).map(([k, v]) => k + ' ' + v + ' s').join(', '));
        div.append(table);
      }
      const details = document.createElement('details');
      details.innerHTML = '<summary>full report</summary><pre></pre>';
      details.querySelector('pre').textContent = json ? JSON.stringify(json, null, 2) : r.report;
      div.append(details);
    });
  }

  // ---- rendering, and what the tests use ---------------------------------------------------------
  // Changes ask for a frame; one is drawn per animation frame (a large mesh in software
  // rendering takes seconds per frame, and loading alone changes the view several times).
  let frameRequested = false, loaded = false;
  function render() {
    if (frameRequested || !loaded) return;
    frameRequested = true;
    requestAnimationFrame(() => { frameRequested = false; renderNow(); });
  }
  function renderNow() { renderer.render(scene, camera); }
  function timeFrame() {
    // One full frame, waited for (readPixels), to decide whether turning needs decimated meshes.
    const gl = renderer.getContext(), start = performance.now();
    renderNow();
    gl.readPixels(0, 0, 1, 1, gl.RGBA, gl.UNSIGNED_BYTE, new Uint8Array(4));
    fullFrameMs = performance.now() - start;
  }
  function notice(text) {
    api.notices.push(text);
    const d = document.createElement('div');
    d.className = 'notice'; d.textContent = text;
    document.getElementById('notices').append(d);
  }
  window.addEventListener('resize', resize);

  api.setLayers = (s) => { Object.assign(state, s); update(); if ('layout' in s) resetCamera(); renderNow(); };
  api.resetCamera = () => { resetCamera(); renderNow(); };
  api.state = () => Object.assign({}, state);
  api.pairs = () => pairs.map((p) => [p.t, p.n]);
  api.warnings = () => Array.from(document.querySelectorAll('#warnings .warning')).map((d) => d.textContent);
  api.correspondencesText = correspondencesText;
  api.screenOfPoint = (kind, point) => {
    // Where a point given in the files' coordinates is drawn beside the template or the network,
    // in CSS pixels of the page, and the direction to the eye (for tests to aim their clicks).
    const p = new THREE.Vector3((point[0] - origin[0]) * scale, (point[1] - origin[1]) * scale, (point[2] - origin[2]) * scale)
      .applyMatrix4((kind === 'template' ? templateGroup : targetGroup).matrixWorld);
    const q = p.clone().project(camera);
    const r = renderer.domElement.getBoundingClientRect();
    const eye = camera.position.clone().sub(p);
    return { x: r.left + (q.x + 1) / 2 * r.width, y: r.top + (1 - q.y) / 2 * r.height, eye: [eye.x, eye.y, eye.z] };
  };
  api.orbitBenchmark = (n, asWhileTurning) => {
    // n frames, each turned 360/n degrees about the target; readPixels waits for each frame.
    timeFrame();
    turning = !!asWhileTurning && useProxies();
    update();
    const gl = renderer.getContext(), pixel = new Uint8Array(4);
    const start = performance.now();
    for (let k = 0; k < n; ++k) {
      const offset = camera.position.clone().sub(controls.target).applyAxisAngle(new THREE.Vector3(0, 1, 0), 2 * Math.PI / n);
      camera.position.copy(controls.target).add(offset);
      camera.lookAt(controls.target);
      renderNow();
      gl.readPixels(0, 0, 1, 1, gl.RGBA, gl.UNSIGNED_BYTE, pixel);
    }
    const ms = (performance.now() - start) / n;
    turning = false;
    update();
    controls.update();
    return ms;
  };

  showReports();
  later.forEach(notice);
  resize();
  update();
  resetCamera();
  pairsChanged();
  loaded = true;
  mark('panel');
  timeFrame();
  mark('first_frame');
  api.loadMs = performance.now() - t0;
  api.sinceNavigationMs = performance.now();
  api.ready = true;
})();
