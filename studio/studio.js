// poreshell studio: the viewer's scene plus a control panel over the studio's HTTP API (docs/studio.md).
// Every edit is one undo step and starts a preview (the server cancels the one still running); Make
// streams its progress as Server-Sent Events. three.js r111 and OrbitControls are embedded in the page.
(function () {
  'use strict';
  const token = new URLSearchParams(location.search).get('token') || '';
  const $ = (id) => document.getElementById(id);
  const api = (path, init = {}) =>
    fetch(path, Object.assign({}, init, { headers: Object.assign({ 'X-Poreshell-Token': token }, init.headers || {}) }));
  const decode = (text) => {
    const binary = atob(text);
    const bytes = new Uint8Array(binary.length);
    for (let i = 0; i < binary.length; ++i) bytes[i] = binary.charCodeAt(i);
    return bytes.buffer;
  };
  const encode = (buffer) => {
    const bytes = new Uint8Array(buffer);
    let binary = '';
    for (let i = 0; i < bytes.length; i += 0x8000) binary += String.fromCharCode.apply(null, bytes.subarray(i, i + 0x8000));
    return btoa(binary);
  };
  const fmt = (v, unit, digits = 1) => (v === null || v === undefined || !isFinite(v) ? '-' : v.toFixed(digits) + (unit ? ' ' + unit : ''));

  // ---- state: what an undo step restores --------------------------------------------------------------
  let info = {}, defaults = {};
  let model = null;  // the upload's answer plus positions (mm, unscaled), indices and the file's bytes
  let state = { options: { hole_diameter: 8, spacing: 14 }, by: 'spacing', grade: { axis: '', from: '', to: '' },
                keepOuts: [], mask: null, selected: -1 };
  const undoStack = [], redoStack = [];
  const snapshot = () => ({ options: Object.assign({}, state.options), by: state.by, grade: Object.assign({}, state.grade),
                            keepOuts: state.keepOuts.map((k) => k.slice()), mask: state.mask ? state.mask.slice() : null,
                            selected: state.selected });
  function commit(change) {
    undoStack.push(snapshot());
    redoStack.length = 0;
    change();
    refresh();
  }
  function restore(from, to) {
    if (!from.length) return;
    to.push(snapshot());
    state = from.pop();
    refresh();
  }
  function refresh() {
    writePanel();
    drawZones();
    preview();
  }

  // ---- the panel's fields, from the library's option table ----------------------------------------------
  function buildFields() {
    for (const el of document.querySelectorAll('.field[data-option]')) {
      const name = el.dataset.option, o = info[name] || { type: 'number', unit: '' };
      const label = document.createElement('label');
      label.textContent = name.replace(/_/g, ' ');
      label.htmlFor = 'opt-' + name;
      label.title = o.help || '';
      let input;
      if (o.type === 'choice') {
        input = document.createElement('select');
        for (const c of o.choices.split(',')) input.add(new Option(c.trim(), c.trim()));
      } else {
        input = document.createElement('input');
        input.type = 'number';
        input.step = 'any';
        if (o.max > o.min) { input.min = o.min; input.max = o.max; }
        const d = defaults[name];
        input.placeholder = d === null || d === undefined || (typeof d === 'number' && !isFinite(d)) ? 'auto' : String(d);
      }
      input.id = 'opt-' + name;
      input.title = (o.help || '') + (o.max > o.min ? ` (${o.min_open ? '>' : '≥'} ${o.min}, ${o.max_open ? '<' : '≤'} ${o.max})` : '');
      const unit = document.createElement('span');
      unit.className = 'unit';
      unit.textContent = o.unit || '';
      el.append(label, input, unit);
      const msg = document.createElement('div');
      msg.className = 'msg';
      msg.id = 'msg-' + name;
      el.after(msg);
      input.addEventListener('change', () => { studio.log.push(['change', performance.now()]); commit(readPanel); });
    }
    for (const id of ['by', 'grade-axis', 'grade-from', 'grade-to']) $(id).addEventListener('change', () => commit(readPanel));
  }
  function readPanel() {
    state.options = {};
    for (const el of document.querySelectorAll('.field[data-option]')) {
      const input = el.querySelector('input, select');
      if (input.value !== '') state.options[el.dataset.option] = input.type === 'number' ? Number(input.value) : input.value;
    }
    state.by = $('by').value;
    state.grade = { axis: $('grade-axis').value, from: $('grade-from').value, to: $('grade-to').value };
  }
  function writePanel() {
    for (const el of document.querySelectorAll('.field[data-option]')) {
      const input = el.querySelector('input, select'), v = state.options[el.dataset.option];
      input.value = v === undefined ? (input.tagName === 'SELECT' ? String(defaults[el.dataset.option] || '') : '') : v;
    }
    $('by').value = state.by;
    $('opt-spacing').closest('.field').hidden = state.by !== 'spacing';
    $('opt-porosity').closest('.field').hidden = state.by !== 'porosity';
    $('grade-axis').value = state.grade.axis;
    $('grade-from').value = state.grade.from;
    $('grade-to').value = state.grade.to;
    for (const el of document.querySelectorAll('.grade')) el.hidden = !state.grade.axis;
    if (model) {
      const s = state.options.scale || 1;
      $('size').textContent = model.size_mm.map((v) => (v * s).toFixed(1)).join(' × ') + ' mm';
    }
    listKeepOuts();
    drawPaint();
  }
  // The options as the API takes them: the library's names, keep-outs as [[x, y, z, r], ...].
  function requestOptions() {
    const o = Object.assign({}, state.options);
    delete o[state.by === 'spacing' ? 'porosity' : 'spacing'];
    if (state.grade.axis && state.grade.from !== '' && state.grade.to !== '')
      o.grade = { kind: 'axis', axis: 'xyz'.indexOf(state.grade.axis), from_diameter: Number(state.grade.from),
                  to_diameter: Number(state.grade.to) };
    if (state.keepOuts.length) o.keep_out = state.keepOuts.map((k) => k.slice());
    return o;
  }
  const painted = () => state.mask && state.mask.some((v) => v);
  let shownSurface = null;  // the painted surface on screen: {id, positions, indices}
  function requestBody() {
    const body = { model: model.id, options: requestOptions() };
    if (shownSurface && shownSurface.model === model.id) body.surface_id = shownSurface.id;
    if (painted()) body.keep_out_mask_values = Array.from(state.mask);
    return body;
  }
  function clearMessages() {
    for (const el of document.querySelectorAll('.msg')) el.textContent = '';
    for (const el of document.querySelectorAll('.field.bad')) el.classList.remove('bad');
  }
  // The library's message at the field it names.
  function showError(body) {
    clearMessages();
    const field = body.option && $('opt-' + body.option);
    if (field) field.closest('.field').classList.add('bad');
    const msg = body.option && $('msg-' + body.option);
    (msg || $('status')).textContent = body.error;
  }

  // ---- the scene -------------------------------------------------------------------------------------
  const view = $('view');
  const renderer = new THREE.WebGLRenderer({ antialias: true });
  renderer.setPixelRatio(window.devicePixelRatio || 1);
  view.prepend(renderer.domElement);
  const scene = new THREE.Scene();
  scene.background = new THREE.Color(0xe9ecef);
  const camera = new THREE.PerspectiveCamera(35, 1, 0.1, 1e5);
  scene.add(new THREE.HemisphereLight(0xffffff, 0x6a635a, 0.5));
  const key = new THREE.DirectionalLight(0xffffff, 0.6);
  camera.add(key);
  key.position.set(1, 1, 2);
  scene.add(camera);
  const material = new THREE.MeshStandardMaterial({ vertexColors: THREE.VertexColors, roughness: 0.8, metalness: 0, side: THREE.DoubleSide });
  let surface = null, zones = new THREE.Group(), paint = null, controls = null, upAxis = 'z';
  scene.add(zones);
  const BASE = new THREE.Color(0xd8cbb3), HOLE = new THREE.Color(0x2d3440);
  const raycaster = new THREE.Raycaster();

  // Only the colours where the surface on screen has these very arrays (a preview of the same split).
  function recolour(positions, colourOf) {
    if (!surface || surface.geometry.getAttribute('position').array !== positions) return false;
    const colours = surface.geometry.getAttribute('color');
    for (let v = 0; v < positions.length / 3; ++v) colourOf(v).toArray(colours.array, 3 * v);
    colours.needsUpdate = true;
    render();
    return true;
  }
  function setSurface(positions, indices, colourOf) {
    if (surface) { scene.remove(surface); surface.geometry.dispose(); }
    const g = new THREE.BufferGeometry();
    g.setAttribute('position', new THREE.BufferAttribute(positions, 3));
    const colours = new Float32Array(positions.length);
    for (let v = 0; v < positions.length / 3; ++v) colourOf(v).toArray(colours, 3 * v);
    g.setAttribute('color', new THREE.BufferAttribute(colours, 3));
    g.computeBoundingSphere();
    if (indices.length) {
      g.setIndex(new THREE.BufferAttribute(indices, 1));
      g.computeVertexNormals();
      surface = new THREE.Mesh(g, material);
    } else {  // a point cloud until its first preview
      surface = new THREE.Points(g, new THREE.PointsMaterial({ vertexColors: THREE.VertexColors, size: 2, sizeAttenuation: false }));
      raycaster.params.Points.threshold = g.boundingSphere.radius / 200;
    }
    scene.add(surface);
    render();
  }
  function scaledModelPositions() {
    const s = state.options.scale || 1, p = model.positions.slice();
    for (let i = 0; i < p.length; ++i) p[i] *= s;
    return p;
  }
  function showModel() {
    setSurface(scaledModelPositions(), model.indices, () => BASE);
  }
  function fit() {
    if (!surface) return;
    const sphere = surface.geometry.boundingSphere;
    const up = new THREE.Vector3(upAxis === 'x' ? 1 : 0, upAxis === 'y' ? 1 : 0, upAxis === 'z' ? 1 : 0);
    camera.up.copy(up);
    const front = upAxis === 'y' ? new THREE.Vector3(0, 0, 1) : new THREE.Vector3(0, -1, 0);
    const right = new THREE.Vector3().crossVectors(up, front);
    const direction = front.addScaledVector(right, 0.5).addScaledVector(up, 0.4).normalize();
    const distance = sphere.radius / Math.sin((camera.fov / 360) * Math.PI) * 1.1;
    camera.near = sphere.radius / 100;
    camera.far = sphere.radius * 40;
    camera.position.copy(sphere.center).addScaledVector(direction, distance);
    if (controls) controls.dispose();
    controls = new THREE.OrbitControls(camera, renderer.domElement);
    controls.screenSpacePanning = true;
    controls.target.copy(sphere.center);
    controls.addEventListener('change', render);
    controls.enabled = tool === 'orbit' || tool === 'sphere';
    controls.update();
    $('btn-up').textContent = 'Up: ' + upAxis.toUpperCase();
    resize();
  }
  function resize() {
    renderer.setSize(view.clientWidth, view.clientHeight, false);
    camera.aspect = view.clientWidth / Math.max(1, view.clientHeight);
    camera.updateProjectionMatrix();
    render();
  }
  // One draw a frame however many changes asked for one: software GL (a headless test, a VM) takes a good
  // part of a second for a preview's surface.
  let frame = 0;
  function render() {
    if (!frame) frame = requestAnimationFrame(() => { frame = 0; renderer.render(scene, camera); });
  }
  window.addEventListener('resize', resize);

  function drawZones() {
    zones.children.slice().forEach((c) => { zones.remove(c); c.geometry.dispose(); });
    state.keepOuts.forEach((k, i) => {
      const m = new THREE.Mesh(new THREE.SphereBufferGeometry(k[3], 24, 16),
        new THREE.MeshBasicMaterial({ color: i === state.selected ? 0xf0a030 : 0x3a8fd0, transparent: true, opacity: 0.35, depthWrite: false }));
      m.position.set(k[0], k[1], k[2]);
      m.userData.index = i;
      zones.add(m);
    });
    render();
  }
  // The painted vertices as dots over the surface.
  function drawPaint() {
    if (paint) { scene.remove(paint); paint.geometry.dispose(); paint = null; }
    if (!model || !painted()) return render();
    const s = state.options.scale || 1, p = [];
    state.mask.forEach((v, i) => { if (v) p.push(model.positions[3 * i] * s, model.positions[3 * i + 1] * s, model.positions[3 * i + 2] * s); });
    const g = new THREE.BufferGeometry();
    g.setAttribute('position', new THREE.BufferAttribute(new Float32Array(p), 3));
    paint = new THREE.Points(g, new THREE.PointsMaterial({ color: 0xe07a2e, size: 3, sizeAttenuation: false }));
    scene.add(paint);
    render();
  }
  function listKeepOuts() {
    const list = $('keepouts');
    list.textContent = '';
    state.keepOuts.forEach((k, i) => {
      const li = document.createElement('li');
      if (i === state.selected) li.className = 'selected';
      // The centre, typed as "x, y, z" (mm): how a sphere is moved.
      const where = document.createElement('input');
      where.type = 'text';
      where.title = 'centre x, y, z, mm';
      where.value = k.slice(0, 3).map((v) => v.toFixed(1)).join(', ');
      where.addEventListener('change', () => {
        const c = where.value.split(',').map(Number);
        if (c.length === 3 && c.every(isFinite)) commit(() => { state.keepOuts[i].splice(0, 3, ...c); });
        else where.value = k.slice(0, 3).map((v) => v.toFixed(1)).join(', ');
      });
      const r = document.createElement('input');
      r.type = 'number'; r.min = '0.1'; r.step = 'any'; r.value = k[3]; r.title = 'radius, mm';
      r.addEventListener('change', () => commit(() => { state.keepOuts[i][3] = Number(r.value); }));
      const del = document.createElement('button');
      del.textContent = '×'; del.title = 'delete';
      del.addEventListener('click', () => commit(() => { state.keepOuts.splice(i, 1); state.selected = -1; }));
      li.addEventListener('click', (e) => { if (e.target === li) { state.selected = i; listKeepOuts(); drawZones(); } });
      where.addEventListener('focus', () => { if (state.selected !== i) { state.selected = i; drawZones(); } });
      li.append(where, r, del);
      list.append(li);
    });
  }

  // ---- tools: view, keep-out spheres, the brush -------------------------------------------------------
  let tool = 'orbit';
  for (const t of ['orbit', 'sphere', 'paint', 'erase'])
    $('tool-' + t).addEventListener('click', () => {
      tool = t;
      for (const u of ['orbit', 'sphere', 'paint', 'erase']) $('tool-' + u).classList.toggle('on', u === t);
      if (controls) controls.enabled = t === 'orbit' || t === 'sphere';
    });
  function hit(e, objects) {
    const rect = renderer.domElement.getBoundingClientRect();
    raycaster.setFromCamera(new THREE.Vector2(((e.clientX - rect.left) / rect.width) * 2 - 1,
                                              -((e.clientY - rect.top) / rect.height) * 2 + 1), camera);
    const hits = raycaster.intersectObjects(objects);
    return hits.length ? hits[0] : null;
  }
  function brush(point, value) {
    const s = state.options.scale || 1, r2 = Math.pow(Number($('brush').value) || 1, 2), p = model.positions;
    for (let i = 0; i < state.mask.length; ++i) {
      const dx = p[3 * i] * s - point.x, dy = p[3 * i + 1] * s - point.y, dz = p[3 * i + 2] * s - point.z;
      if (dx * dx + dy * dy + dz * dz <= r2) state.mask[i] = value;
    }
  }
  let down = null, stroke = null;
  renderer.domElement.addEventListener('pointerdown', (e) => {
    down = { x: e.clientX, y: e.clientY };
    if ((tool === 'paint' || tool === 'erase') && surface && state.mask) {
      const h = hit(e, [surface]);
      if (!h) return;
      stroke = snapshot();
      brush(h.point, tool === 'paint' ? 1 : 0);
      drawPaint();
    }
  });
  renderer.domElement.addEventListener('pointermove', (e) => {
    if (!stroke) return;
    const h = hit(e, [surface]);
    if (h) { brush(h.point, tool === 'paint' ? 1 : 0); drawPaint(); }
  });
  window.addEventListener('pointerup', (e) => {
    if (stroke) {
      undoStack.push(stroke);
      redoStack.length = 0;
      stroke = null;
      refresh();
      return;
    }
    const click = down && Math.hypot(e.clientX - down.x, e.clientY - down.y) < 5 && e.target === renderer.domElement;
    down = null;
    if (!click || tool !== 'sphere' || !surface) return;
    const onZone = hit(e, zones.children);
    if (onZone) {
      state.selected = onZone.object.userData.index;
      listKeepOuts();
      drawZones();
      return;
    }
    const h = hit(e, [surface]);
    if (!h) return;
    const r = Math.max(5, 1.25 * (state.options.hole_diameter || 8));
    commit(() => { state.keepOuts.push([h.point.x, h.point.y, h.point.z, Number(r.toFixed(2))]); state.selected = state.keepOuts.length - 1; });
  });
  window.addEventListener('keydown', (e) => {
    if (e.target.tagName === 'INPUT') return;
    if ((e.key === 'Delete' || e.key === 'Backspace') && state.selected >= 0)
      commit(() => { state.keepOuts.splice(state.selected, 1); state.selected = -1; });
    if ((e.ctrlKey || e.metaKey) && e.key === 'z') restore(e.shiftKey ? redoStack : undoStack, e.shiftKey ? undoStack : redoStack);
  });
  $('undo').addEventListener('click', () => restore(undoStack, redoStack));
  $('redo').addEventListener('click', () => restore(redoStack, undoStack));
  $('btn-fit').addEventListener('click', fit);
  $('btn-up').addEventListener('click', () => { upAxis = { x: 'y', y: 'z', z: 'x' }[upAxis]; fit(); });

  // ---- model -----------------------------------------------------------------------------------------
  async function openModel(bytes, name, units) {
    $('status').textContent = 'reading ' + name + '…';
    const res = await api(`/api/model?name=${encodeURIComponent(name)}&units=${units}`, { method: 'POST', body: bytes });
    const body = await res.json();
    if (!res.ok) { $('status').textContent = body.error; return false; }
    const keepMask = model && state.mask && state.mask.length === body.vertices ? state.mask : null;
    model = Object.assign(body, { positions: new Float32Array(decode(body.mesh.positions)),
                                  indices: new Uint32Array(decode(body.mesh.indices)), bytes: bytes });
    delete model.mesh;
    state.mask = body.kind === 'mesh' ? keepMask || new Uint8Array(body.vertices) : null;
    $('title').textContent = name;
    $('units').value = body.units;
    upAxis = /\.(obj|ply)$/i.test(name) ? 'y' : 'z';
    showModel();
    fit();
    refresh();
    return true;
  }
  async function openFile(file) {
    if (file) await openModel(await file.arrayBuffer(), file.name, $('units').value);
  }
  $('file').addEventListener('change', () => openFile($('file').files[0]));
  $('units').addEventListener('change', () => { if (model) openModel(model.bytes, model.name, $('units').value); });
  view.addEventListener('dragover', (e) => { e.preventDefault(); view.classList.add('dragging'); });
  view.addEventListener('dragleave', () => view.classList.remove('dragging'));
  view.addEventListener('drop', (e) => {
    e.preventDefault();
    view.classList.remove('dragging');
    openFile(e.dataTransfer.files[0]);
  });

  // ---- preview ---------------------------------------------------------------------------------------
  let previewAbort = null, previewCount = 0;
  const studio = (window.studio = { log: [], preview: null, previews: 0, state: () => state, requestBody: () => requestBody() });
  async function preview() {
    if (!model) return;
    if (previewAbort) previewAbort.abort();
    const abort = (previewAbort = new AbortController());
    const n = ++previewCount;
    studio.log.push(['start', n, performance.now()]);
    $('status').textContent = 'preview…';
    let res, body;
    try {
      res = await api('/api/preview', { method: 'POST', body: JSON.stringify(requestBody()), signal: abort.signal,
                                        headers: { 'Content-Type': 'application/json' } });
      studio.log.push(['response', n, performance.now()]);
      body = await res.json();
      studio.log.push(['parsed', n, performance.now()]);
    } catch (e) {
      return;  // aborted by a newer edit
    }
    if (n !== previewCount || res.status === 409) return;
    if (!res.ok) return showError(body);
    clearMessages();
    showPreview(body);
    studio.preview = body;
    studio.previews += 1;
  }
  function showPreview(p) {
    const f = p.figures;
    $('fig-holes').textContent = String(p.holes);
    $('fig-diameter').textContent = fmt(f.diameter, 'mm');
    $('fig-spacing').textContent = fmt(f.spacing, 'mm');
    $('fig-porosity').textContent = fmt(100 * f.porosity, '%');
    $('fig-wall').textContent = fmt(f.wall, 'mm');
    $('fig-ligament').textContent = fmt(f.ligament, 'mm');
    $('fig-mass').textContent = fmt(f.mass, 'g');
    $('status').textContent = `preview in ${p.seconds.toFixed(2)} s` + (p.warnings.length ? ' · ' + p.warnings.join(' · ') : '');
    const n = previewCount;
    setTimeout(() => { if (n === previewCount) paintPreview(p); }, 0);  // the figures first
  }
  function paintPreview(p) {
    const pattern = new Float32Array(decode(p.surface.pattern));
    // The server leaves out the surface the page shows already (the id it was sent): recoloured only.
    if (p.surface.positions)
      shownSurface = { id: p.surface.id, model: model.id, positions: new Float32Array(decode(p.surface.positions)),
                       indices: new Uint32Array(decode(p.surface.indices)) };
    if (!shownSurface || shownSurface.id !== p.surface.id) return;
    const colourOf = (v) => (pattern[v] > 0 ? HOLE : BASE);
    if (!recolour(shownSurface.positions, colourOf)) setSurface(shownSurface.positions, shownSurface.indices, colourOf);
  }

  // ---- make ------------------------------------------------------------------------------------------
  let job = null, events = null;
  $('make').addEventListener('click', async () => {
    if (!model) return;
    $('files').textContent = '';
    $('made').hidden = true;
    const res = await api('/api/make', { method: 'POST', body: JSON.stringify(requestBody()), headers: { 'Content-Type': 'application/json' } });
    const body = await res.json();
    if (!res.ok) { showError(body); $('make-status').textContent = body.error; return; }
    job = body.job;
    $('cancel').disabled = false;
    $('make').disabled = true;
    events = new EventSource(`/api/jobs/${job}/events?token=${token}`);
    events.onmessage = (e) => {
      const s = JSON.parse(e.data);
      $('progress-bar').style.width = (100 * s.fraction).toFixed(1) + '%';
      $('make-status').textContent = `${s.state} ${s.stage || ''} ${(100 * s.fraction).toFixed(0)}%` +
        (s.eta !== null && s.state === 'running' ? ` · ${Math.ceil(s.eta)} s left` : '');
      if (['done', 'failed', 'cancelled'].includes(s.state)) { events.close(); finished(s); }
    };
    events.onerror = () => events.close();
  });
  $('cancel').addEventListener('click', () => { if (job) api(`/api/jobs/${job}`, { method: 'DELETE' }); });
  async function finished(s) {
    $('cancel').disabled = true;
    $('make').disabled = false;
    if (s.state !== 'done') { $('make-status').textContent = s.state + (s.error ? ': ' + s.error : ''); return; }
    const full = await (await api(`/api/jobs/${job}`)).json();
    studio.job = full;
    const m = full.report.mesh, holes = m.hole_table || [];
    const mean = holes.reduce((a, h) => a + h.diameter, 0) / Math.max(1, holes.length);
    $('make-status').textContent = `done: ${holes.length} holes, mean ${mean.toFixed(2)} mm, wall ${fmt(m.wall && m.wall.measured_median_mm, 'mm', 2)}, ` +
      `${m.closed && m.manifold ? 'closed and manifold' : 'NOT closed'}, ${m.parts.count} part(s), ${fmt(m.volume * 1.24e-3, 'g')} PLA`;
    showMade(m, holes);
    for (const name of full.files) {
      const li = document.createElement('li'), a = document.createElement('a');
      a.href = `/api/jobs/${job}/files/${name}?token=${token}`;
      a.download = name;
      a.textContent = name;
      li.append(a);
      $('files').append(li);
    }
    showResult(await (await api(`/api/jobs/${job}/files/part.stl`)).arrayBuffer(), holes);
  }
  // The made part measured as the report has it: the holes on the mesh, its wall, rim, keep-outs and part.
  function showMade(m, holes) {
    const mean = (xs) => xs.reduce((a, x) => a + x, 0) / Math.max(1, xs.length);
    const cv = (xs) => { const u = mean(xs); return Math.sqrt(mean(xs.map((x) => (x - u) * (x - u)))) / (u || 1); };
    const d = holes.map((h) => h.diameter), s = holes.filter((h) => h.nearest > 0).map((h) => h.nearest);
    const w = m.wall || {}, a = m.applied || {};
    $('made-holes').textContent = String(holes.length);
    $('made-diameter').textContent = `${fmt(mean(d), 'mm', 2)} · CV ${fmt(100 * cv(d), '%')}`;
    $('made-spacing').textContent = `${fmt(mean(s), 'mm', 2)} · CV ${fmt(100 * cv(s), '%')}`;
    $('made-porosity').textContent = fmt(100 * m.holes.porosity, '%');
    $('made-wall').textContent = `${fmt(w.measured_median_mm, 'mm', 2)} (${fmt(w.measured_p5_mm, '', 2)}-${fmt(w.measured_p95_mm, 'mm', 2)})`;
    $('made-rim').textContent = a.rim_measured_mm === null ? '-' : `${fmt(a.rim_measured_mm, 'mm')} (asked ${fmt(a.rim_requested_mm, 'mm')})`;
    $('made-clearance').textContent = a.keep_outs ? `${fmt(a.keep_out_clearance_mm, 'mm')}, ${a.holes_in_keep_outs} holes in` : '-';
    $('made-part').textContent = `${m.closed && m.manifold && m.oriented ? 'closed, manifold' : 'NOT PRINTABLE'}, ${m.parts.count} part(s)`;
    $('made-triangles').textContent = m.triangles.toLocaleString('en');
    $('made-mass').textContent = `${fmt(m.volume / 1000, 'cm³', 2)}, ${fmt(m.volume * 1.24e-3, 'g')}`;
    $('made').hidden = false;
  }
  // The printed part, its holes' rims coloured by the diameter's deviation from the one asked.
  function showResult(stl, holes) {
    const data = new DataView(stl), count = data.getUint32(80, true);
    const positions = new Float32Array(count * 9), indices = new Uint32Array(count * 3);
    for (let t = 0; t < count; ++t)
      for (let k = 0; k < 9; ++k) positions[9 * t + k] = data.getFloat32(84 + 50 * t + 12 + 4 * k, true);
    for (let i = 0; i < indices.length; ++i) indices[i] = i;
    // Holes bucketed by a grid of cells as large as the largest hole, so that a vertex looks at 27 cells.
    const cell = Math.max(1, ...holes.map((h) => h.diameter)) + 2, grid = new Map();
    const keyOf = (x, y, z) => `${Math.floor(x / cell)},${Math.floor(y / cell)},${Math.floor(z / cell)}`;
    for (const h of holes) {
      const k = keyOf(h.centre[0], h.centre[1], h.centre[2]);
      grid.set(k, (grid.get(k) || []).concat([h]));
    }
    const colourOf = (v) => {
      const x = positions[3 * v], y = positions[3 * v + 1], z = positions[3 * v + 2];
      const i = Math.floor(x / cell), j = Math.floor(y / cell), k = Math.floor(z / cell);
      for (let a = i - 1; a <= i + 1; ++a)
        for (let b = j - 1; b <= j + 1; ++b)
          for (let c = k - 1; c <= k + 1; ++c)
            for (const h of grid.get(`${a},${b},${c}`) || []) {
              const p = h.centre;
              if (Math.hypot(x - p[0], y - p[1], z - p[2]) < 0.5 * h.diameter + 1.0) {
                const dev = Math.max(-1, Math.min(1, (h.diameter - h.asked_diameter) / (0.15 * h.asked_diameter || 1)));
                return new THREE.Color().setHSL(0.33 - 0.33 * dev, 0.6, 0.5);
              }
            }
      return BASE;
    };
    setSurface(positions, indices, colourOf);
  }

  // ---- project: one JSON file -------------------------------------------------------------------------
  // Test hook: the preview's hole centres whose nearest model vertex is painted.
  studio.centresInPaint = () => {
    const s = state.options.scale || 1, p = model.positions;
    let inside = 0;
    for (const c of studio.preview.centres) {
      let best = Infinity, at = -1;
      for (let i = 0; i < state.mask.length; ++i) {
        const d = Math.pow(p[3 * i] * s - c[0], 2) + Math.pow(p[3 * i + 1] * s - c[1], 2) + Math.pow(p[3 * i + 2] * s - c[2], 2);
        if (d < best) { best = d; at = i; }
      }
      if (at >= 0 && state.mask[at]) ++inside;
    }
    return inside;
  };
  studio.project = () => ({
    poreshell_project: 1,
    model: { name: model.name, units: model.units, data: encode(model.bytes) },
    options: requestOptions(),
    keep_out_mask_values: painted() ? Array.from(state.mask) : undefined,
  });
  $('save').addEventListener('click', () => {
    if (!model) return;
    const a = document.createElement('a');
    a.href = URL.createObjectURL(new Blob([JSON.stringify(studio.project())], { type: 'application/json' }));
    a.download = model.name.replace(/\.[^.]*$/, '') + '.poreshell.json';
    a.click();
  });
  $('open').addEventListener('click', () => $('project-file').click());
  $('project-file').addEventListener('change', async () => {
    const p = JSON.parse(await $('project-file').files[0].text());
    undoStack.push(snapshot());
    const o = Object.assign({}, p.options);
    state.keepOuts = (o.keep_out || []).map((k) => (Array.isArray(k) ? k.slice() : [...k.centre, k.radius]));
    const g = o.grade && typeof o.grade === 'object' && o.grade.kind === 'axis' ? o.grade : null;
    state.grade = g ? { axis: 'xyz'[g.axis], from: String(g.from_diameter), to: String(g.to_diameter) } : { axis: '', from: '', to: '' };
    state.by = o.porosity ? 'porosity' : 'spacing';
    delete o.keep_out;
    delete o.grade;
    state.options = o;
    state.mask = null;
    if (await openModel(decode(p.model.data), p.model.name, p.model.units) && p.keep_out_mask_values)
      state.mask = Uint8Array.from(p.keep_out_mask_values);
    refresh();
  });

  // ---- start -----------------------------------------------------------------------------------------
  (async () => {
    const table = await (await api('/api/options')).json();
    for (const o of table.options) info[o.name] = o;
    defaults = table.defaults;
    buildFields();
    const health = await (await api('/api/health')).json();
    if (health.scale !== 1) state.options.scale = health.scale;
    writePanel();
    resize();
    if (health.model !== null) {
      const bytes = await (await api(`/api/model/${health.model}/file`)).arrayBuffer();
      const m = await (await api(`/api/model/${health.model}`)).json();
      $('units').value = m.units;
      await openModel(bytes, m.name, m.units);
    }
    studio.ready = true;
  })();
})();
