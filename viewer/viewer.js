// poreshell viewer: the shell, its holes coloured by diameter, keep-out zones, and the run's figures.
// Reads the JSON in the script element #poreshell-data (written by src/io/html_viewer.cpp) and three.js r111
// with its OrbitControls, both embedded in the page. No network.
(function () {
  'use strict';

  function decodeBase64(text) {
    const binary = atob(text), bytes = new Uint8Array(binary.length);
    for (let i = 0; i < binary.length; ++i) bytes[i] = binary.charCodeAt(i);
    return bytes.buffer;
  }
  const floats = (text) => new Float32Array(decodeBase64(text));
  const data = JSON.parse(document.getElementById('poreshell-data').textContent);
  const report = data.report || {};
  const meshReport = report.mesh || {};

  // centre x y z, normal x y z, diameter, circularity, nearest neighbour, axis ratio, asked diameter
  const HOLE_STRIDE = 11;
  const holeValues = data.holes.count > 0 ? floats(data.holes.data) : new Float32Array(0);
  const holes = [];
  for (let i = 0; i < data.holes.count; ++i) {
    const v = holeValues.subarray(i * HOLE_STRIDE, (i + 1) * HOLE_STRIDE);
    const normal = new THREE.Vector3(v[3], v[4], v[5]);
    if (normal.lengthSq() > 0) normal.normalize();
    holes.push({
      index: i, centre: new THREE.Vector3(v[0], v[1], v[2]), normal: normal,
      diameter: v[6], circularity: v[7], nearest: v[8], axisRatio: v[9], asked: v[10],
    });
  }

  // ---- figures -------------------------------------------------------------------------------------
  function meanCv(values) {
    if (values.length === 0) return null;
    const mean = values.reduce((a, b) => a + b, 0) / values.length;
    const variance = values.reduce((a, b) => a + (b - mean) * (b - mean), 0) / values.length;
    return { mean: mean, cv: mean > 0 ? Math.sqrt(variance) / mean : 0 };
  }
  const finite = (x) => typeof x === 'number' && isFinite(x);
  const fmt = (x, digits) => (finite(x) ? x.toFixed(digits) : '–');
  const mm = (x, digits = 2) => (finite(x) ? fmt(x, digits) + ' mm' : '–');
  const pct = (x, digits = 1) => (finite(x) ? (100 * x).toFixed(digits) + ' %' : '–');

  const diameters = holes.map((h) => h.diameter);
  const spacings = holes.map((h) => h.nearest).filter((x) => x > 0);
  const reportHoles = meshReport.holes || {};
  const dStats = meanCv(diameters), sStats = meanCv(spacings);
  const figures = {
    count: finite(reportHoles.count) ? reportHoles.count : holes.length,
    diameterMean: finite(reportHoles.diameter_mean_mm) ? reportHoles.diameter_mean_mm : dStats && dStats.mean,
    diameterCv: finite(reportHoles.diameter_cv) ? reportHoles.diameter_cv : dStats && dStats.cv,
    spacingMean: finite(reportHoles.spacing_mean_mm) ? reportHoles.spacing_mean_mm : sStats && sStats.mean,
    spacingCv: finite(reportHoles.spacing_cv) ? reportHoles.spacing_cv : sStats && sStats.cv,
    porosity: reportHoles.porosity,
  };
  const requested = (report.holes && report.holes.requested) || {};
  const requestedDiameter = finite(data.requested_diameter_mm) ? data.requested_diameter_mm : requested.diameter_mm;
  // Holes are coloured by their deviation from the diameter asked at each (graded or not), or from their
  // mean where none was asked.
  const reference = finite(requestedDiameter) ? requestedDiameter : (figures.diameterMean || 1);
  const askedOf = (h) => (h.asked > 0 ? h.asked : reference);
  const graded = holes.some((h) => h.asked > 0 && Math.abs(h.asked - reference) > 1e-3 * reference);
  const deviation = (h) => h.diameter / askedOf(h) - 1;
  const SPAN = 0.25;  // the colour scale's ends: ±25 %

  function row(list, label, value, sub) {
    const dt = document.createElement('dt');
    dt.textContent = label;
    const dd = document.createElement('dd');
    dd.textContent = value;
    if (sub) {
      const s = document.createElement('span');
      s.className = 'sub';
      s.textContent = ' ' + sub;
      dd.appendChild(s);
    }
    list.append(dt, dd);
    return dd;
  }

  // The 5th to 95th percentiles, and apart from them the probes that crossed a part thinner than two
  // walls (solid there): a minimum to maximum range would read as an error on an ear or a finger.
  function wallSpread(wall) {
    let spread = fmt(wall.measured_p5_mm, 2) + '–' + fmt(wall.measured_p95_mm, 2) + ' (90%)';
    if (wall.merged_probes > 0) spread += '; solid up to ' + mm(wall.measured_max_mm) + ' where thinner than two walls';
    return spread;
  }

  function fillPanel() {
    const req = document.getElementById('request');
    const wall = meshReport.wall || {};
    const solid = report.solid || {};
    if (finite(requestedDiameter)) row(req, 'Hole diameter', mm(requestedDiameter));
    if (finite(requested.spacing_mm)) row(req, 'Spacing', mm(requested.spacing_mm));
    if (finite(requested.porosity) && requested.porosity > 0) row(req, 'Porosity', pct(requested.porosity));
    // Graded: the sizes asked over the surface, as clamped to what prints.
    const grading = (report.holes || {}).grading;
    const grade = (report.settings || {}).grade;
    if (grading && grade)
      row(req, 'Graded (' + grade.kind + ')', fmt(grading.min_diameter_mm, 2) + '–' + mm(grading.max_diameter_mm),
          grading.clamped_fraction > 0 ? pct(grading.clamped_fraction) + ' clamped' : undefined);
    // A preview makes no wall: the request shows one only where it was asked for.
    const preview = report.preview === true;
    const wallAsked = !preview || (finite((report.settings || {}).wall) && report.settings.wall > 0);
    const wallRequested = finite(wall.requested_mm) ? wall.requested_mm : solid.wall_mm;
    const wallSource = { default: 'default for holes in mm', band: "the band's width" }[solid.wall_source];
    if (wallAsked && finite(wallRequested)) row(req, 'Wall', mm(wallRequested), wallSource);
    if (!req.children.length) req.outerHTML = '<div class="none">no hole request (model parameters)</div>';

    const m = document.getElementById('measured');
    row(m, 'Holes', String(figures.count)).id = 'hole-count';
    row(m, 'Diameter', mm(figures.diameterMean), 'CV ' + pct(figures.diameterCv));
    row(m, 'Spacing', mm(figures.spacingMean), 'CV ' + pct(figures.spacingCv));
    if (finite(figures.porosity)) row(m, 'Porosity', pct(figures.porosity));
    // A preview has no solid: no wall, triangle count, volume or mass to show (its report holds zeros).
    if (!preview && finite(wall.measured_median_mm))
      row(m, 'Wall', mm(wall.measured_median_mm), wallSpread(wall));
    if (!preview && finite(meshReport.triangles)) row(m, 'Triangles', meshReport.triangles.toLocaleString('en'));
    if (preview) {
      document.getElementById('print').outerHTML =
          '<div class="none" id="print">a preview: the surface and its holes, no solid yet</div>';
    } else {
      // Volume: the report's (mm³), else the display mesh's own.
      const volume = finite(meshReport.volume) ? meshReport.volume : meshVolume;
      const density = document.getElementById('density');
      density.value = data.density_g_per_cm3;
      document.getElementById('volume').textContent = fmt(volume / 1000, 2) + ' cm³';
      const updateMass = () => {
        const rho = parseFloat(density.value);
        document.getElementById('mass').textContent = finite(rho) && rho > 0 ? fmt((volume / 1000) * rho, 1) + ' g' : '–';
      };
      density.addEventListener('input', updateMass);
      updateMass();
    }

    // Asked, and what the holes left: the nearest hole's edge from the open boundary and from a keep-out.
    const z = document.getElementById('zones');
    const applied = meshReport.applied || {};
    row(z, 'Rim', data.rim_width_mm > 0 ? mm(data.rim_width_mm, 1) : 'none');
    if (data.rim_width_mm > 0 && finite(applied.rim_measured_mm)) row(z, 'Rim left', mm(applied.rim_measured_mm, 1));
    row(z, 'Keep-out spheres', String(data.keep_out_spheres.length));
    row(z, 'Keep-out boxes', String(data.keep_out_boxes.length));
    if (finite(applied.keep_out_clearance_mm))
      row(z, 'Keep-out clearance', applied.holes_in_keep_outs > 0 ? applied.holes_in_keep_outs + ' holes reach in'
                                                                   : mm(applied.keep_out_clearance_mm, 1));

    const files = document.getElementById('files');
    const paths = (meshReport.outputs || []).map((o) => o.path).filter((p) => p);
    if (!paths.length && meshReport.path) paths.push(meshReport.path);
    for (const p of paths) {
      const li = document.createElement('li');
      li.textContent = p;
      files.appendChild(li);
    }
    if (!paths.length) files.innerHTML = '<li class="none">none recorded</li>';
  }

  // ---- colours -------------------------------------------------------------------------------------
  const COLD = new THREE.Color('#3b6fd4'), GOOD = new THREE.Color('#2fa37a'), HOT = new THREE.Color('#e0523a');
  const BASE = new THREE.Color('#d8d2c8');
  const OPEN = new THREE.Color('#3a3f47');  // a preview's open vertices away from every hole record
  function deviationColour(relative) {
    const t = Math.max(-1, Math.min(1, relative / SPAN));
    return t < 0 ? GOOD.clone().lerp(COLD, -t) : GOOD.clone().lerp(HOT, t);
  }
  const cssColour = (c) => '#' + c.getHexString();

  function drawLegend() {
    document.querySelector('#legend .bar').style.background =
        'linear-gradient(to right, ' + cssColour(COLD) + ', ' + cssColour(GOOD) + ', ' + cssColour(HOT) + ')';
    document.getElementById('legend-lo').textContent = graded ? '−25 %' : fmt(reference * (1 - SPAN), 2) + ' (−25 %)';
    document.getElementById('legend-mid').textContent = graded ? 'as asked' : fmt(reference, 2);
    document.getElementById('legend-hi').textContent = graded ? '+25 %' : fmt(reference * (1 + SPAN), 2) + ' (+25 %)';
    document.getElementById('legend-caption').textContent = graded
        ? 'hole colour: diameter against the graded size asked at each hole'
        : 'hole colour: diameter (mm) against the ' + (finite(requestedDiameter) ? 'request' : 'mean');
  }

  function drawHistogram() {
    const canvas = document.getElementById('histogram');
    const ctx = canvas.getContext('2d');
    const W = canvas.width, H = canvas.height, left = 40, bottom = 34, top = 12, right = 24;
    ctx.clearRect(0, 0, W, H);
    ctx.font = '20px sans-serif';
    ctx.fillStyle = '#8b95a3';
    if (!diameters.length) {
      ctx.fillText('no holes', W / 2 - 40, H / 2);
      return;
    }
    let lo = Math.min(reference * (1 - SPAN), ...diameters), hi = Math.max(reference * (1 + SPAN), ...diameters);
    const bins = Math.max(8, Math.min(40, Math.round(Math.sqrt(diameters.length) * 2)));
    const width = (hi - lo) / bins;
    const counts = new Array(bins).fill(0), deviations = new Array(bins).fill(0);
    for (const h of holes) {
      const bin = Math.min(bins - 1, Math.floor((h.diameter - lo) / width));
      counts[bin]++;
      deviations[bin] += deviation(h);
    }
    const maxCount = Math.max(...counts);
    const x = (d) => left + ((d - lo) / (hi - lo)) * (W - left - right);
    const y = (c) => H - bottom - (c / maxCount) * (H - bottom - top);
    for (let i = 0; i < bins; ++i) {
      // A bin's colour is its holes' mean deviation from what each was asked (graded sizes differ).
      ctx.fillStyle = cssColour(deviationColour(counts[i] ? deviations[i] / counts[i] : 0));
      ctx.fillRect(x(lo + i * width) + 1, y(counts[i]), x(lo + (i + 1) * width) - x(lo + i * width) - 2, H - bottom - y(counts[i]));
    }
    ctx.strokeStyle = '#3a4250';
    ctx.lineWidth = 2;
    ctx.beginPath();
    ctx.moveTo(left, H - bottom);
    ctx.lineTo(W - right, H - bottom);
    ctx.stroke();
    ctx.fillStyle = '#8b95a3';
    ctx.textAlign = 'center';
    for (let k = 0; k <= 4; ++k) {
      const d = lo + (k / 4) * (hi - lo);
      ctx.fillText(d.toFixed(1), x(d), H - 8);
    }
    ctx.textAlign = 'right';
    ctx.fillText(String(maxCount), left - 6, top + 14);
    ctx.fillText('0', left - 6, H - bottom);
    // The request, where one size was asked: a dashed line.
    if (finite(requestedDiameter) && !graded) {
      ctx.strokeStyle = '#dfe4ea';
      ctx.setLineDash([6, 5]);
      ctx.beginPath();
      ctx.moveTo(x(requestedDiameter), top);
      ctx.lineTo(x(requestedDiameter), H - bottom);
      ctx.stroke();
      ctx.setLineDash([]);
    }
  }

  // ---- scene ---------------------------------------------------------------------------------------
  const view = document.getElementById('view');
  const renderer = new THREE.WebGLRenderer({ antialias: true, preserveDrawingBuffer: true });
  renderer.setPixelRatio(window.devicePixelRatio || 1);
  renderer.setClearColor(0xe9ecef);
  view.insertBefore(renderer.domElement, view.firstChild);
  const scene = new THREE.Scene();
  const camera = new THREE.PerspectiveCamera(35, 1, 0.1, 1000);

  const positions = floats(data.mesh.positions);
  const indices = new Uint32Array(decodeBase64(data.mesh.indices));
  const geometry = new THREE.BufferGeometry();
  geometry.setAttribute('position', new THREE.BufferAttribute(positions, 3));
  geometry.setIndex(new THREE.BufferAttribute(indices, 1));
  geometry.computeVertexNormals();
  geometry.computeBoundingBox();
  geometry.computeBoundingSphere();
  // A preview's pattern: phi minus the pore level per vertex, open where positive (absent otherwise).
  const pattern = data.mesh.pattern ? floats(data.mesh.pattern) : null;
  const colours = new Float32Array(positions.length);
  geometry.setAttribute('color', new THREE.BufferAttribute(colours, 3));

  let meshVolume = 0;  // mm³, by the divergence theorem
  for (let t = 0; t < indices.length; t += 3) {
    const a = 3 * indices[t], b = 3 * indices[t + 1], c = 3 * indices[t + 2];
    meshVolume += (positions[a] * (positions[b + 1] * positions[c + 2] - positions[b + 2] * positions[c + 1]) +
                   positions[a + 1] * (positions[b + 2] * positions[c] - positions[b] * positions[c + 2]) +
                   positions[a + 2] * (positions[b] * positions[c + 1] - positions[b + 1] * positions[c])) / 6;
  }

  // Paint is tested per pixel (the shader below): a hole's colour shows where `paint`, interpolated across
  // each triangle, is positive, so the coloured edge is a contour and not a blend of vertex colours that
  // frays along every triangle it crosses. A preview's paint is its pattern (open where positive); a
  // run's is how far inside a hole's reach (1.3 radii, its rim on the surface) a vertex is. Vertices
  // carry their hole's colour some way past that edge, so that no triangle across it blends colours.
  const paint = pattern ? pattern : new Float32Array(positions.length / 3);
  geometry.setAttribute('paint', new THREE.BufferAttribute(paint, 1));
  let edgeLength = 0;  // mean, over the first triangles: how far past the edge colours must reach
  const sampled = Math.min(indices.length, 30000);
  for (let t = 0; t < sampled; t += 3) {
    const a = 3 * indices[t], b = 3 * indices[t + 1];
    edgeLength += Math.hypot(positions[a] - positions[b], positions[a + 1] - positions[b + 1],
                             positions[a + 2] - positions[b + 2]) / (sampled / 3);
  }
  const margin = 1.5 * edgeLength;

  // A hole's colour goes to the vertices within its reach that its own cut joins by edges within that
  // reach: the rims on both faces of the wall, and not another sheet of the surface that passes within
  // it (a fold: the bunny's chin over its neck), which a test by distance alone painted. Each hole's
  // fill starts at its cut: the vertices within 1.15 radii of its axis and within the wall (a preview:
  // the surface) of its centre's plane, with room for the surface's curve.
  const reach = holes.map((h) => 0.5 * h.diameter * 1.3 + 0.2);
  const halfWall = pattern ? 0 : 0.5 * (finite((report.solid || {}).wall_mm) ? report.solid.wall_mm : 0);
  let neighbours = null;  // each vertex's neighbours (CSR), built at the first fill
  function vertexNeighbours() {
    const n = positions.length / 3;
    const start = new Uint32Array(n + 1);
    for (let t = 0; t < indices.length; ++t) start[indices[t] + 1] += 2;
    for (let v = 0; v < n; ++v) start[v + 1] += start[v];
    const list = new Uint32Array(start[n]), next = start.slice(0, n);
    for (let t = 0; t < indices.length; t += 3)
      for (let k = 0; k < 3; ++k) {
        const a = indices[t + k];
        list[next[a]++] = indices[t + (k + 1) % 3];
        list[next[a]++] = indices[t + (k + 2) % 3];
      }
    return { start, list };
  }
  function colourVertices(show) {
    for (let i = 0; i < colours.length; i += 3) (show && pattern ? OPEN : BASE).toArray(colours, i);
    const vertexCount = positions.length / 3;
    const inside = new Float32Array(vertexCount).fill(-margin);  // how deep in the reach of `best`
    const best = new Int32Array(vertexCount).fill(-1);
    if (show && holes.length) {
      // A cell grid of the hole centres finds each hole's vertices within its reach plus the margin.
      const cell = Math.max(...reach) + margin;
      const grid = new Map();
      const key = (i, j, k) => i + ',' + j + ',' + k;
      holes.forEach((h, n) => {
        const k = key(Math.floor(h.centre.x / cell), Math.floor(h.centre.y / cell), Math.floor(h.centre.z / cell));
        if (!grid.has(k)) grid.set(k, []);
        grid.get(k).push(n);
      });
      const near = holes.map(() => []);
      for (let v = 0; v < positions.length; v += 3) {
        const px = positions[v], py = positions[v + 1], pz = positions[v + 2];
        const ci = Math.floor(px / cell), cj = Math.floor(py / cell), ck = Math.floor(pz / cell);
        for (let i = ci - 1; i <= ci + 1; ++i)
          for (let j = cj - 1; j <= cj + 1; ++j)
            for (let k = ck - 1; k <= ck + 1; ++k)
              for (const n of grid.get(key(i, j, k)) || []) {
                const c = holes[n].centre;
                if (Math.hypot(px - c.x, py - c.y, pz - c.z) < reach[n] + margin) near[n].push(v / 3);
              }
      }
      neighbours = neighbours || vertexNeighbours();
      const seen = new Int32Array(vertexCount).fill(-1);
      holes.forEach((h, n) => {
        const c = h.centre, m = h.normal, r = 0.5 * h.diameter;
        const distance = (v) => Math.hypot(positions[3 * v] - c.x, positions[3 * v + 1] - c.y, positions[3 * v + 2] - c.z);
        const isCut = (v) => {
          const x = positions[3 * v] - c.x, y = positions[3 * v + 1] - c.y, z = positions[3 * v + 2] - c.z;
          const axial = x * m.x + y * m.y + z * m.z;
          return Math.abs(axial) <= halfWall + 0.15 * r && x * x + y * y + z * z - axial * axial <= (1.15 * r) ** 2;
        };
        let queue = near[n].filter(isCut);
        if (queue.length === 0) queue = near[n];  // no cut found: by distance alone
        for (const v of queue) seen[v] = n;
        for (let q = 0; q < queue.length; ++q) {
          const v = queue[q];
          const depth = reach[n] - distance(v);
          if (depth > inside[v]) {
            inside[v] = depth;
            best[v] = n;
          }
          for (let e = neighbours.start[v]; e < neighbours.start[v + 1]; ++e) {
            const w = neighbours.list[e];
            if (seen[w] === n || distance(w) >= reach[n] + margin) continue;
            seen[w] = n;
            queue.push(w);
          }
        }
      });
      const holeColours = holes.map((h) => deviationColour(deviation(h)));
      for (let v = 0; v < vertexCount; ++v)
        if (best[v] >= 0) holeColours[best[v]].toArray(colours, 3 * v);
    }
    if (!pattern) paint.set(inside);
    geometry.attributes.color.needsUpdate = true;
    geometry.attributes.paint.needsUpdate = true;
  }
  colourVertices(true);

  const material = new THREE.MeshStandardMaterial({
    vertexColors: THREE.VertexColors, roughness: 0.62, metalness: 0.0, side: THREE.DoubleSide,
  });
  material.onBeforeCompile = (shader) => {
    shader.vertexShader = shader.vertexShader
      .replace('#include <common>', '#include <common>\nattribute float paint;\nvarying float vPaint;')
      .replace('#include <begin_vertex>', '#include <begin_vertex>\nvPaint = paint;');
    const base = BASE.toArray().map((c) => c.toFixed(4)).join(', ');
    shader.fragmentShader = shader.fragmentShader
      .replace('#include <common>', '#include <common>\nvarying float vPaint;')
      .replace('#include <color_fragment>', `diffuseColor.rgb *= vPaint > 0.0 ? vColor : vec3(${base});`);
  };
  const mesh = new THREE.Mesh(geometry, material);
  scene.add(mesh);

  const box = geometry.boundingBox;
  const centre = box.getCenter(new THREE.Vector3());
  const size = box.getSize(new THREE.Vector3()).length() || 1;

  scene.add(new THREE.HemisphereLight(0xffffff, 0x6a635a, 0.45));
  const key = new THREE.DirectionalLight(0xffffff, 0.6);
  const fill = new THREE.DirectionalLight(0xc8d8ff, 0.2);
  camera.add(key, fill);  // lights move with the camera: the side in view is always lit
  key.position.set(1.5, 2, 1);
  fill.position.set(-2, -0.5, 1);
  scene.add(camera);

  // Solid zones: wireframe spheres and boxes, rim loops as lines.
  const zones = new THREE.Group();
  // Each outline twice: solid where in front of the surface, faint where behind it.
  const zoneMaterials = [
    new THREE.LineBasicMaterial({ color: 0xb03a8c, transparent: true, opacity: 0.85 }),
    new THREE.LineBasicMaterial({ color: 0xb03a8c, transparent: true, opacity: 0.22, depthTest: false }),
  ];
  function addZone(geometry, x, y, z) {
    for (const m of zoneMaterials) {
      const lines = new THREE.LineSegments(geometry, m);
      lines.position.set(x, y, z);
      zones.add(lines);
    }
  }
  for (const [x, y, z, r] of data.keep_out_spheres)
    addZone(new THREE.WireframeGeometry(new THREE.SphereBufferGeometry(r, 24, 12)), x, y, z);
  for (const [x0, y0, z0, x1, y1, z1] of data.keep_out_boxes) {
    const edges = new THREE.EdgesGeometry(new THREE.BoxBufferGeometry(Math.abs(x1 - x0), Math.abs(y1 - y0), Math.abs(z1 - z0)));
    addZone(edges, (x0 + x1) / 2, (y0 + y1) / 2, (z0 + z1) / 2);
  }
  const rimMaterial = new THREE.LineBasicMaterial({ color: 0xd08a1c });
  for (const loop of data.rim_loops) {
    const g = new THREE.BufferGeometry();
    g.setAttribute('position', new THREE.BufferAttribute(floats(loop), 3));
    zones.add(new THREE.LineLoop(g, rimMaterial));
  }
  scene.add(zones);

  // The selected hole: a ring drawn over everything.
  const ring = new THREE.LineLoop(new THREE.BufferGeometry(), new THREE.LineBasicMaterial({ color: 0x111111, depthTest: false }));
  {
    const points = [];
    for (let i = 0; i < 64; ++i) points.push(Math.cos((i / 64) * 2 * Math.PI), Math.sin((i / 64) * 2 * Math.PI), 0);
    ring.geometry.setAttribute('position', new THREE.BufferAttribute(new Float32Array(points), 3));
  }
  ring.renderOrder = 10;
  ring.visible = false;
  scene.add(ring);
  const marker = new THREE.Mesh(new THREE.SphereBufferGeometry(1, 16, 8), new THREE.MeshBasicMaterial({ color: 0x111111, depthTest: false }));
  marker.renderOrder = 10;
  marker.visible = false;
  scene.add(marker);

  let controls = null;
  const UP = { x: new THREE.Vector3(1, 0, 0), y: new THREE.Vector3(0, 1, 0), z: new THREE.Vector3(0, 0, 1) };
  let upAxis = UP[data.up_axis] ? data.up_axis : 'z';
  function fit() {
    const up = UP[upAxis];
    camera.up.copy(up);
    // Looked at from the front (-y, or -z with y up, -y with x up), a little from the right and above.
    const front = upAxis === 'y' ? UP.z.clone() : UP.y.clone().negate();
    const right = new THREE.Vector3().crossVectors(up, front);
    const direction = front.addScaledVector(right, 0.55).addScaledVector(up, 0.45).normalize();
    const distance = (0.5 * size) / Math.sin((camera.fov / 360) * Math.PI);
    camera.near = size / 500;
    camera.far = size * 20;
    camera.position.copy(centre).addScaledVector(direction, distance * 1.05);
    // OrbitControls takes the up direction when it is made: a new one for each.
    if (controls) controls.dispose();
    controls = new THREE.OrbitControls(camera, renderer.domElement);
    controls.screenSpacePanning = true;
    controls.target.copy(centre);
    controls.addEventListener('change', render);
    controls.update();
    document.getElementById('btn-up').textContent = 'Up: ' + upAxis.toUpperCase();
    resize();
  }

  function resize() {
    const w = view.clientWidth, h = view.clientHeight;
    renderer.setSize(w, h, false);
    camera.aspect = w / Math.max(1, h);
    camera.updateProjectionMatrix();
    render();
  }

  function render() {
    renderer.render(scene, camera);
  }

  // ---- picking -------------------------------------------------------------------------------------
  const raycaster = new THREE.Raycaster();
  function rayAt(clientX, clientY) {
    const rect = renderer.domElement.getBoundingClientRect();
    const ndc = new THREE.Vector2(((clientX - rect.left) / rect.width) * 2 - 1, -((clientY - rect.top) / rect.height) * 2 + 1);
    raycaster.setFromCamera(ndc, camera);
    return raycaster.ray;
  }

  // The hole whose disc (centre, normal, diameter) the ray crosses first, unless the surface is
  // clearly in front of it; else the surface point.
  function pick(clientX, clientY) {
    const ray = rayAt(clientX, clientY);
    const hits = raycaster.intersectObject(mesh);
    const surface = hits.length ? hits[0] : null;
    let best = null;
    const plane = new THREE.Plane(), point = new THREE.Vector3();
    for (const h of holes) {
      const normal = h.normal.lengthSq() > 0 ? h.normal : ray.direction.clone().negate();
      plane.setFromNormalAndCoplanarPoint(normal, h.centre);
      if (!ray.intersectPlane(plane, point)) continue;
      if (point.distanceTo(h.centre) > 0.55 * h.diameter) continue;
      const t = point.distanceTo(ray.origin);
      if (surface && t > surface.distance + 0.5 * h.diameter) continue;
      if (!best || t < best.t) best = { hole: h, t: t };
    }
    if (best) return { hole: best.hole };
    if (surface) return { point: surface.point };
    return null;
  }

  const selection = document.getElementById('selection');
  function showHole(h) {
    const dev = deviation(h);
    const swatch = '<span class="swatch" style="background:' + cssColour(deviationColour(dev)) + '"></span>';
    selection.className = 'hole';
    selection.innerHTML = '<h3>' + swatch + 'Hole ' + (h.index + 1) + ' of ' + holes.length + '</h3><dl></dl>';
    const list = selection.querySelector('dl');
    row(list, 'Diameter', mm(h.diameter)).id = 'sel-diameter';
    if (h.asked > 0) row(list, 'Asked', mm(h.asked)).id = 'sel-asked';
    row(list, h.asked > 0 || finite(requestedDiameter) ? 'vs asked' : 'vs mean', (dev >= 0 ? '+' : '') + pct(dev));
    if (h.circularity > 0) {  // a preview's holes are the band's spots: no loop measured
      row(list, 'Circularity', fmt(h.circularity, 3));
      row(list, 'Axis ratio', fmt(h.axisRatio, 3));
    }
    row(list, 'Nearest hole', mm(h.nearest));
    row(list, 'Centre', [h.centre.x, h.centre.y, h.centre.z].map((c) => c.toFixed(2)).join(', '));
    selection.dataset.hole = String(h.index);
    ring.position.copy(h.centre);
    ring.scale.setScalar(0.5 * h.diameter);
    ring.lookAt(h.centre.clone().add(h.normal.lengthSq() > 0 ? h.normal : UP.z));
    ring.visible = true;
    marker.visible = false;
  }
  function showPoint(p) {
    const text = [p.x, p.y, p.z].map((c) => c.toFixed(2));
    selection.className = 'point';
    selection.innerHTML = '<h3>Surface point (mm, input frame)</h3><dl></dl>' +
        '<code id="keep-out-arg">--keep-out ' + text.join(',') + ',' + fmt(Math.max(1, reference), 1) + '</code>';
    const list = selection.querySelector('dl');
    row(list, 'x', text[0]);
    row(list, 'y', text[1]);
    row(list, 'z', text[2]);
    selection.dataset.point = text.join(',');
    delete selection.dataset.hole;
    marker.position.copy(p);
    marker.scale.setScalar(size / 250);
    marker.visible = true;
    ring.visible = false;
  }

  // A click is a press and release without a drag (a drag orbits).
  let down = null;
  renderer.domElement.addEventListener('pointerdown', (e) => { down = { x: e.clientX, y: e.clientY }; });
  renderer.domElement.addEventListener('pointerup', (e) => {
    if (!down || Math.hypot(e.clientX - down.x, e.clientY - down.y) > 4 || e.button !== 0) return;
    const picked = pick(e.clientX, e.clientY);
    if (picked && picked.hole) showHole(picked.hole);
    else if (picked) showPoint(picked.point);
    render();
  });

  // ---- toolbar -------------------------------------------------------------------------------------
  function toggle(id, apply) {
    const button = document.getElementById(id);
    button.addEventListener('click', () => {
      button.classList.toggle('on');
      apply(button.classList.contains('on'));
      render();
    });
  }
  toggle('btn-holes', (on) => colourVertices(on));
  toggle('btn-zones', (on) => { zones.visible = on; });
  document.getElementById('btn-fit').addEventListener('click', fit);
  document.getElementById('btn-up').addEventListener('click', () => {
    upAxis = { x: 'y', y: 'z', z: 'x' }[upAxis];
    fit();
  });
  window.addEventListener('resize', resize);

  fillPanel();
  drawLegend();
  drawHistogram();
  fit();

  // For tests and scripts: where a model point lands on the screen (client pixels), and whether the
  // surface there faces the camera.
  window.poreshellViewer = {
    holeCount: holes.length,
    project(x, y, z, nx = 0, ny = 0, nz = 0) {
      const p = new THREE.Vector3(x, y, z);
      const facing = new THREE.Vector3(nx, ny, nz).dot(camera.position.clone().sub(p)) > 0;
      const ndc = p.clone().project(camera);
      const rect = renderer.domElement.getBoundingClientRect();
      return {
        x: rect.left + ((ndc.x + 1) / 2) * rect.width, y: rect.top + ((1 - ndc.y) / 2) * rect.height,
        inView: Math.abs(ndc.x) < 1 && Math.abs(ndc.y) < 1 && ndc.z < 1, facing: facing,
      };
    },
    // The cosine between a normal at a point and the direction from there to the camera.
    facing(x, y, z, nx, ny, nz) {
      const toCamera = camera.position.clone().sub(new THREE.Vector3(x, y, z)).normalize();
      return new THREE.Vector3(nx, ny, nz).normalize().dot(toCamera);
    },
    cameraPosition: () => camera.position.toArray(),
  };
  document.body.dataset.ready = '1';
})();
