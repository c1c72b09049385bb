// skelseg viewer: draws the data block of viewer.html with WebGL 1.
//
// The page is self-contained: the data (a JSON block written by
// io/render/ViewerWriter.cpp, arrays as base64 of little-endian typed arrays)
// and this script are inlined, nothing is fetched. Text from the input (file
// name, grid name) only ever reaches the page through textContent.
//
// State can be set from the URL hash, e.g. viewer.html#level=1&skeleton=rho_c
// (and pick=x,y clicks at a canvas pixel),
// and from window.skelsegViewer (setLevel, setSkeletonColouring); the page
// sets document.body.dataset.rendered to the number of frames drawn, which
// the headless-browser test reads back.
'use strict';

(function () {
  const data = JSON.parse(document.getElementById('skelseg-data').textContent);
  const canvas = document.getElementById('view');
  const byId = (id) => document.getElementById(id);

  function decode(base64, Type) {
    const text = atob(base64 || '');
    const bytes = new Uint8Array(text.length);
    for (let i = 0; i < text.length; ++i) bytes[i] = text.charCodeAt(i);
    return new Type(bytes.buffer);
  }

  // ---- data -----------------------------------------------------------------
  const surface = {
    positions: decode(data.surface.positions, Float32Array),
    indices: decode(data.surface.indices, Uint32Array),
  };
  // Per vertex: index of its base segment (a segment of the finest level);
  // base segment s owns the vertices from vertexStarts[s] to the next start.
  surface.baseSegment = new Uint32Array(surface.positions.length / 3);
  data.surface.vertexStarts.forEach((start, s) => surface.baseSegment.fill(s, start));
  const skeleton = {
    positions: decode(data.skeleton.positions, Float32Array),
    edges: decode(data.skeleton.edges, Uint32Array),
    sigma: decode(data.skeleton.sigma, Float32Array),
    rhoC: decode(data.skeleton.rhoC, Float32Array),
  };
  const levels = data.levels.map((level) => ({
    tau: level.tau,
    segments: level.segments,
    baseLabel: decode(level.baseLabel, Uint32Array),
    cutPositions: decode(level.cuts.positions, Float32Array),
    cutLoopStarts: level.cuts.loopStarts,
  }));
  const segmentByLabel = levels.map((level) => {
    const map = new Map();
    for (const s of level.segments) map.set(s.id, s);
    return map;
  });

  byId('title').textContent = data.title;
  document.title = 'skelseg: ' + data.title;
  byId('facts').textContent = data.facts.join(' \u00b7 ');

  // ---- WebGL set-up ---------------------------------------------------------
  const gl = canvas.getContext('webgl', { antialias: true, preserveDrawingBuffer: true });
  if (!gl || !gl.getExtension('OES_element_index_uint')) {
    byId('error').textContent = 'This browser offers no WebGL (with 32-bit indices): nothing to draw.';
    document.body.dataset.rendered = '-1';
    return;
  }

  function program(vertexSource, fragmentSource) {
    const p = gl.createProgram();
    for (const [type, source] of [[gl.VERTEX_SHADER, vertexSource], [gl.FRAGMENT_SHADER, fragmentSource]]) {
      const s = gl.createShader(type);
      gl.shaderSource(s, source);
      gl.compileShader(s);
      if (!gl.getShaderParameter(s, gl.COMPILE_STATUS)) throw new Error(gl.getShaderInfoLog(s));
      gl.attachShader(p, s);
    }
    gl.linkProgram(p);
    if (!gl.getProgramParameter(p, gl.LINK_STATUS)) throw new Error(gl.getProgramInfoLog(p));
    return p;
  }

  // Surface: Lambert from a head light, two-sided (meshes may be open or
  // inconsistently oriented). The pick variant writes base segment + 1 as RGB.
  const surfaceProgram = program(`
    attribute vec3 position; attribute vec3 normal; attribute vec3 colour;
    uniform mat4 viewProjection; uniform mat4 view;
    varying vec3 vColour; varying vec3 vNormal;
    void main() {
      vColour = colour; vNormal = (view * vec4(normal, 0.0)).xyz;
      gl_Position = viewProjection * vec4(position, 1.0);
    }`, `
    precision mediump float;
    varying vec3 vColour; varying vec3 vNormal;
    void main() {
      float light = abs(normalize(vNormal).z);
      gl_FragColor = vec4(vColour * (0.35 + 0.65 * light), 1.0);
    }`);
  const pickProgram = program(`
    attribute vec3 position; attribute float segment;
    uniform mat4 viewProjection; varying vec3 vId;
    void main() {
      float id = segment + 1.0;
      vId = vec3(mod(id, 256.0), mod(floor(id / 256.0), 256.0), floor(id / 65536.0)) / 255.0;
      gl_Position = viewProjection * vec4(position, 1.0);
    }`, `
    precision highp float; varying vec3 vId;
    void main() { gl_FragColor = vec4(vId, 1.0); }`);
  const lineProgram = program(`
    attribute vec3 position; attribute vec3 colour;
    uniform mat4 viewProjection; varying vec3 vColour;
    void main() { vColour = colour; gl_Position = viewProjection * vec4(position, 1.0); }`, `
    precision mediump float; varying vec3 vColour; uniform float alpha;
    void main() { gl_FragColor = vec4(vColour, alpha); }`);

  function buffer(target, array) {
    const b = gl.createBuffer();
    gl.bindBuffer(target, b);
    gl.bufferData(target, array, gl.STATIC_DRAW);
    return b;
  }

  function vertexNormals(positions, indices) {
    const normals = new Float32Array(positions.length);
    for (let t = 0; t < indices.length; t += 3) {
      const a = 3 * indices[t], b = 3 * indices[t + 1], c = 3 * indices[t + 2];
      const ux = positions[b] - positions[a], uy = positions[b + 1] - positions[a + 1], uz = positions[b + 2] - positions[a + 2];
      const vx = positions[c] - positions[a], vy = positions[c + 1] - positions[a + 1], vz = positions[c + 2] - positions[a + 2];
      const nx = uy * vz - uz * vy, ny = uz * vx - ux * vz, nz = ux * vy - uy * vx;
      for (const v of [a, b, c]) { normals[v] += nx; normals[v + 1] += ny; normals[v + 2] += nz; }
    }
    return normals;
  }

  const surfaceBuffers = {
    position: buffer(gl.ARRAY_BUFFER, surface.positions),
    normal: buffer(gl.ARRAY_BUFFER, vertexNormals(surface.positions, surface.indices)),
    segment: buffer(gl.ARRAY_BUFFER, Float32Array.from(surface.baseSegment)),
    colour: gl.createBuffer(),
    index: buffer(gl.ELEMENT_ARRAY_BUFFER, surface.indices),
  };

  // Skeleton as line segments, cut loops as closed line strips turned into segments.
  const skeletonLines = new Float32Array(skeleton.edges.length * 3);
  for (let i = 0; i < skeleton.edges.length; ++i)
    skeletonLines.set(skeleton.positions.subarray(3 * skeleton.edges[i], 3 * skeleton.edges[i] + 3), 3 * i);
  const skeletonBuffers = { position: buffer(gl.ARRAY_BUFFER, skeletonLines), colour: gl.createBuffer() };

  function cutLines(level) {
    const points = level.cutPositions, starts = level.cutLoopStarts.concat([points.length / 3]);
    const lines = [];
    for (let l = 0; l + 1 < starts.length; ++l) {
      const n = starts[l + 1] - starts[l];
      for (let i = 0; i < n && n > 1; ++i) {
        if (n === 2 && i === 1) break;  // two points: one edge
        const p = starts[l] + i, q = starts[l] + (i + 1) % n;
        lines.push(points[3 * p], points[3 * p + 1], points[3 * p + 2], points[3 * q], points[3 * q + 1], points[3 * q + 2]);
      }
    }
    return new Float32Array(lines);
  }
  const cutBuffers = levels.map((level) => {
    const lines = cutLines(level);
    const colours = new Float32Array(lines.length);
    for (let i = 0; i < colours.length; i += 3) colours.set([1.0, 0.85, 0.1], i);
    return { position: buffer(gl.ARRAY_BUFFER, lines), colour: buffer(gl.ARRAY_BUFFER, colours), count: lines.length / 3 };
  });

  // ---- state ----------------------------------------------------------------
  const state = { level: 'openLevel' in data ? data.openLevel : levels.length - 1, skeletonColouring: 'sigma', picked: null };

  function setLevel(level) {
    state.level = Math.max(0, Math.min(levels.length - 1, level | 0));
    byId('level').value = String(state.level);
    const current = levels[state.level];
    byId('levelText').textContent = state.level + ' of ' + (levels.length - 1) + ' (tau ' + current.tau + ', ' + current.segments.length + ' parts)';
    const colours = new Float32Array(surface.positions.length);
    for (let v = 0; v < surface.baseSegment.length; ++v) {
      const s = segmentByLabel[state.level].get(current.baseLabel[surface.baseSegment[v]]);
      const rgb = s ? s.colour : [128, 128, 128];
      colours.set([rgb[0] / 255, rgb[1] / 255, rgb[2] / 255], 3 * v);
    }
    gl.bindBuffer(gl.ARRAY_BUFFER, surfaceBuffers.colour);
    gl.bufferData(gl.ARRAY_BUFFER, colours, gl.STATIC_DRAW);
    if (state.picked !== null) showPicked(state.picked);
    draw();
  }

  // Viridis, sampled at nine points and interpolated linearly.
  const viridis = [[68, 1, 84], [71, 44, 122], [59, 81, 139], [44, 113, 142], [33, 144, 141],
    [39, 173, 129], [92, 200, 99], [170, 220, 50], [253, 231, 37]];
  function ramp(t) {
    const x = Math.max(0, Math.min(1, t)) * (viridis.length - 1), i = Math.min(viridis.length - 2, Math.floor(x)), f = x - i;
    return viridis[i].map((c, k) => (c + f * (viridis[i + 1][k] - c)) / 255);
  }

  // rho_C spans orders of magnitude (an area): coloured on a log scale.
  function setSkeletonColouring(name) {
    state.skeletonColouring = name === 'rho_c' ? 'rho_c' : 'sigma';
    for (const input of document.querySelectorAll('input[name=skeletonColour]')) input.checked = input.value === state.skeletonColouring;
    const useLog = state.skeletonColouring === 'rho_c';
    const values = useLog ? skeleton.rhoC : skeleton.sigma;
    const transform = (x) => (useLog ? Math.log10(Math.max(x, 1e-6)) : x);
    let low = Infinity, high = -Infinity;
    for (const x of values) { low = Math.min(low, transform(x)); high = Math.max(high, transform(x)); }
    const span = high > low ? high - low : 1;
    const colours = new Float32Array(skeletonLines.length);
    for (let i = 0; i < skeleton.edges.length; ++i)
      colours.set(ramp((transform(values[skeleton.edges[i]]) - low) / span), 3 * i);
    gl.bindBuffer(gl.ARRAY_BUFFER, skeletonBuffers.colour);
    gl.bufferData(gl.ARRAY_BUFFER, colours, gl.STATIC_DRAW);
    const stops = [0, 0.25, 0.5, 0.75, 1].map((t) => 'rgb(' + ramp(t).map((c) => Math.round(255 * c)).join(',') + ') ' + 100 * t + '%');
    byId('ramp').style.background = 'linear-gradient(to right, ' + stops.join(', ') + ')';
    const show = (x) => (useLog ? Math.pow(10, x) : x).toPrecision(3);
    byId('rampText').textContent = values.length ? show(low) + ' \u2013 ' + show(high) + (useLog ? ' voxels\u00b2' : '') : 'no skeleton';
    draw();
  }

  // ---- camera: orbit around the centre of the bounding box ------------------
  const lo = [Infinity, Infinity, Infinity], hi = [-Infinity, -Infinity, -Infinity];
  for (const points of [surface.positions, skeleton.positions])
    for (let i = 0; i < points.length; ++i) { lo[i % 3] = Math.min(lo[i % 3], points[i]); hi[i % 3] = Math.max(hi[i % 3], points[i]); }
  if (!(lo[0] <= hi[0])) { lo.fill(-1); hi.fill(1); }
  const centre = lo.map((l, a) => 0.5 * (l + hi[a]));
  const radius = Math.max(1e-9, 0.5 * Math.hypot(hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]));
  // The longest side points up (input files disagree on which axis is up).
  const upAxis = [0, 1, 2].reduce((best, a) => (hi[a] - lo[a] > hi[best] - lo[best] ? a : best), 1);
  const camera = { yaw: 0.6, pitch: 0.35, distance: 2.8 };

  function cross(a, b) { return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]; }
  function normalise(a) { const n = Math.hypot(a[0], a[1], a[2]) || 1; return a.map((x) => x / n); }
  function multiply(a, b) {  // column-major 4x4
    const r = new Float32Array(16);
    for (let c = 0; c < 4; ++c) for (let rr = 0; rr < 4; ++rr) {
      let s = 0;
      for (let k = 0; k < 4; ++k) s += a[k * 4 + rr] * b[c * 4 + k];
      r[c * 4 + rr] = s;
    }
    return r;
  }

  function matrices() {
    // Spherical coordinates in a frame whose third axis is the up axis.
    const e2 = [0, 0, 0]; e2[upAxis] = 1;
    const e0 = [0, 0, 0]; e0[(upAxis + 1) % 3] = 1;
    const e1 = cross(e2, e0);
    const d = [Math.cos(camera.pitch) * Math.cos(camera.yaw), Math.cos(camera.pitch) * Math.sin(camera.yaw), Math.sin(camera.pitch)];
    const direction = [0, 1, 2].map((a) => d[0] * e0[a] + d[1] * e1[a] + d[2] * e2[a]);
    const distance = camera.distance * radius;
    const eye = centre.map((c, a) => c + distance * direction[a]);
    const z = normalise(direction), x = normalise(cross(e2, z)), y = cross(z, x);
    const view = new Float32Array([x[0], y[0], z[0], 0, x[1], y[1], z[1], 0, x[2], y[2], z[2], 0,
      -(x[0] * eye[0] + x[1] * eye[1] + x[2] * eye[2]), -(y[0] * eye[0] + y[1] * eye[1] + y[2] * eye[2]),
      -(z[0] * eye[0] + z[1] * eye[1] + z[2] * eye[2]), 1]);
    const aspect = canvas.width / Math.max(1, canvas.height), f = 1 / Math.tan(0.5 * 0.6);
    const near = Math.max(distance - 2 * radius, distance * 0.01), far = distance + 2 * radius;
    const projection = new Float32Array([f / aspect, 0, 0, 0, 0, f, 0, 0, 0, 0, (far + near) / (near - far), -1,
      0, 0, 2 * far * near / (near - far), 0]);
    return { view, viewProjection: multiply(projection, view) };
  }

  // ---- drawing --------------------------------------------------------------
  function attribute(prog, name, buf, size) {
    const location = gl.getAttribLocation(prog, name);
    if (location < 0) return;
    gl.bindBuffer(gl.ARRAY_BUFFER, buf);
    gl.enableVertexAttribArray(location);
    gl.vertexAttribPointer(location, size, gl.FLOAT, false, 0, 0);
  }
  function resetAttributes() { for (let i = 0; i < 4; ++i) gl.disableVertexAttribArray(i); }

  function drawSurface(prog, m) {
    gl.useProgram(prog);
    gl.uniformMatrix4fv(gl.getUniformLocation(prog, 'viewProjection'), false, m.viewProjection);
    const viewLocation = gl.getUniformLocation(prog, 'view');
    if (viewLocation) gl.uniformMatrix4fv(viewLocation, false, m.view);
    resetAttributes();
    attribute(prog, 'position', surfaceBuffers.position, 3);
    attribute(prog, 'normal', surfaceBuffers.normal, 3);
    attribute(prog, 'colour', surfaceBuffers.colour, 3);
    attribute(prog, 'segment', surfaceBuffers.segment, 1);
    gl.bindBuffer(gl.ELEMENT_ARRAY_BUFFER, surfaceBuffers.index);
    gl.drawElements(gl.TRIANGLES, surface.indices.length, gl.UNSIGNED_INT, 0);
  }

  // Lines hidden by the surface are drawn faintly, visible ones in full.
  function drawLines(buffers, count, m) {
    if (!count) return;
    gl.useProgram(lineProgram);
    gl.uniformMatrix4fv(gl.getUniformLocation(lineProgram, 'viewProjection'), false, m.viewProjection);
    resetAttributes();
    attribute(lineProgram, 'position', buffers.position, 3);
    attribute(lineProgram, 'colour', buffers.colour, 3);
    gl.enable(gl.BLEND);
    gl.blendFunc(gl.SRC_ALPHA, gl.ONE_MINUS_SRC_ALPHA);
    gl.depthMask(false);
    gl.depthFunc(gl.GREATER);
    gl.uniform1f(gl.getUniformLocation(lineProgram, 'alpha'), 0.35);
    gl.drawArrays(gl.LINES, 0, count);
    gl.depthFunc(gl.LEQUAL);
    gl.uniform1f(gl.getUniformLocation(lineProgram, 'alpha'), 1.0);
    gl.drawArrays(gl.LINES, 0, count);
    gl.depthMask(true);
    gl.disable(gl.BLEND);
  }

  let frames = 0;
  function draw() {
    const width = Math.max(1, Math.round(canvas.clientWidth * (window.devicePixelRatio || 1)));
    const height = Math.max(1, Math.round(canvas.clientHeight * (window.devicePixelRatio || 1)));
    if (canvas.width !== width || canvas.height !== height) { canvas.width = width; canvas.height = height; }
    gl.viewport(0, 0, canvas.width, canvas.height);
    gl.clearColor(0.957, 0.957, 0.949, 1);
    gl.clear(gl.COLOR_BUFFER_BIT | gl.DEPTH_BUFFER_BIT);
    gl.enable(gl.DEPTH_TEST);
    gl.depthFunc(gl.LEQUAL);
    const m = matrices();
    if (byId('showSurface').checked) drawSurface(surfaceProgram, m);
    if (byId('showSkeleton').checked) drawLines(skeletonBuffers, skeletonLines.length / 3, m);
    if (byId('showCuts').checked) drawLines(cutBuffers[state.level], cutBuffers[state.level].count, m);
    document.body.dataset.rendered = String(++frames);
  }

  // ---- picking: draw base segment ids off screen, read the clicked pixel ----
  // An RGBA/UNSIGNED_BYTE texture is colour-renderable in every WebGL 1, and
  // keeps the 8 bits per channel the ids are written with.
  const pickTarget = { framebuffer: gl.createFramebuffer(), texture: gl.createTexture(), depth: gl.createRenderbuffer() };
  function pick(x, y) {
    const w = canvas.width, h = canvas.height;
    gl.bindTexture(gl.TEXTURE_2D, pickTarget.texture);
    gl.texImage2D(gl.TEXTURE_2D, 0, gl.RGBA, w, h, 0, gl.RGBA, gl.UNSIGNED_BYTE, null);
    gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_MIN_FILTER, gl.NEAREST);
    gl.bindRenderbuffer(gl.RENDERBUFFER, pickTarget.depth);
    gl.renderbufferStorage(gl.RENDERBUFFER, gl.DEPTH_COMPONENT16, w, h);
    gl.bindFramebuffer(gl.FRAMEBUFFER, pickTarget.framebuffer);
    gl.framebufferTexture2D(gl.FRAMEBUFFER, gl.COLOR_ATTACHMENT0, gl.TEXTURE_2D, pickTarget.texture, 0);
    gl.framebufferRenderbuffer(gl.FRAMEBUFFER, gl.DEPTH_ATTACHMENT, gl.RENDERBUFFER, pickTarget.depth);
    const pixel = new Uint8Array(4);
    if (gl.checkFramebufferStatus(gl.FRAMEBUFFER) === gl.FRAMEBUFFER_COMPLETE) {
      gl.viewport(0, 0, w, h);
      gl.clearColor(0, 0, 0, 1);
      gl.clear(gl.COLOR_BUFFER_BIT | gl.DEPTH_BUFFER_BIT);
      gl.enable(gl.DEPTH_TEST);
      drawSurface(pickProgram, matrices());
      gl.readPixels(x, h - 1 - y, 1, 1, gl.RGBA, gl.UNSIGNED_BYTE, pixel);
    }
    gl.bindFramebuffer(gl.FRAMEBUFFER, null);
    draw();
    const id = pixel[0] + 256 * pixel[1] + 65536 * pixel[2];
    return id > 0 ? id - 1 : null;
  }

  function showPicked(baseSegment) {
    state.picked = baseSegment;
    const label = levels[state.level].baseLabel[baseSegment];
    const s = segmentByLabel[state.level].get(label);
    if (!s) { byId('picked').textContent = ''; return; }
    const parent = s.parent === null ? 'none (coarsest level)' : String(s.parent);
    byId('picked').textContent = 'segment ' + s.id + ': ' + s.voxels + ' voxels, parent ' + parent;
  }

  // ---- input ----------------------------------------------------------------
  let drag = null;
  canvas.addEventListener('mousedown', (e) => { drag = { x: e.clientX, y: e.clientY, moved: false }; });
  window.addEventListener('mouseup', (e) => {
    if (drag && !drag.moved) {
      const scale = window.devicePixelRatio || 1, box = canvas.getBoundingClientRect();
      const id = pick(Math.round((e.clientX - box.left) * scale), Math.round((e.clientY - box.top) * scale));
      if (id === null) { state.picked = null; byId('picked').textContent = ''; } else showPicked(id);
    }
    drag = null;
  });
  window.addEventListener('mousemove', (e) => {
    if (!drag) return;
    const dx = e.clientX - drag.x, dy = e.clientY - drag.y;
    if (Math.abs(dx) + Math.abs(dy) > 2) drag.moved = true;
    if (!drag.moved) return;
    camera.yaw -= dx * 0.01;
    camera.pitch = Math.max(-1.55, Math.min(1.55, camera.pitch + dy * 0.01));
    drag.x = e.clientX; drag.y = e.clientY;
    draw();
  });
  canvas.addEventListener('wheel', (e) => {
    e.preventDefault();
    camera.distance = Math.max(0.2, Math.min(20, camera.distance * Math.exp(e.deltaY * 0.001)));
    draw();
  }, { passive: false });
  window.addEventListener('resize', draw);
  byId('level').max = String(levels.length - 1);
  byId('level').addEventListener('input', (e) => setLevel(Number(e.target.value)));
  for (const input of document.querySelectorAll('input[name=skeletonColour]'))
    input.addEventListener('change', () => setSkeletonColouring(input.value));
  for (const id of ['showSurface', 'showSkeleton', 'showCuts']) byId(id).addEventListener('change', draw);
  byId('reset').addEventListener('click', () => { Object.assign(camera, { yaw: 0.6, pitch: 0.35, distance: 2.8 }); draw(); });

  function applyHash() {
    const parameters = new URLSearchParams(location.hash.slice(1));
    if (parameters.has('skeleton')) setSkeletonColouring(parameters.get('skeleton'));
    if (parameters.has('level')) setLevel(Number(parameters.get('level')));
    if (parameters.has('pick')) {  // "x,y" in canvas pixels: a click without a mouse
      const [x, y] = parameters.get('pick').split(',').map(Number);
      const id = pick(x, y);
      if (id === null) byId('picked').textContent = ''; else showPicked(id);
    }
  }
  window.addEventListener('hashchange', applyHash);

  window.skelsegViewer = { setLevel, setSkeletonColouring, pick, levelCount: levels.length };
  setSkeletonColouring('sigma');
  setLevel(state.level);
  applyHash();
})();
