// The `dmgplace view` page: builds the scene from the embedded JSON (typed arrays in base64) and
// plays the arm's motion. World frame z-up, metres. Poses are [x, y, z, qx, qy, qz, qw].
import * as THREE from 'three';
import { OrbitControls } from 'three/addons/controls/OrbitControls.js';

const D = JSON.parse(document.getElementById('dmgplace-data').textContent);
const $ = (id) => document.getElementById(id);
const BG = [0xf4, 0xf5, 0xf7];

// ---- typed arrays and geometry
function buffer(b64) {
  const s = atob(b64 || '');
  const u = new Uint8Array(s.length);
  for (let i = 0; i < s.length; i++) u[i] = s.charCodeAt(i);
  return u.buffer;
}
const f32 = (b64) => new Float32Array(buffer(b64));
const u32 = (b64) => new Uint32Array(buffer(b64));
function geometry(m) {
  const g = new THREE.BufferGeometry();
  g.setAttribute('position', new THREE.BufferAttribute(f32(m.p), 3));
  g.setIndex(new THREE.BufferAttribute(u32(m.i), 1));
  g.computeVertexNormals();
  g.computeBoundingSphere();
  return g;
}
const solid = (color) => new THREE.MeshStandardMaterial({ color, flatShading: true, roughness: 0.7 });
const glass = (color, opacity) => new THREE.MeshStandardMaterial({
  color, flatShading: true, transparent: true, opacity, depthWrite: false, side: THREE.DoubleSide });
function setPose(o, p) {
  o.position.set(p[0], p[1], p[2]);
  o.quaternion.set(p[3], p[4], p[5], p[6]);
}

// ---- renderer, camera, lights
const renderer = new THREE.WebGLRenderer({ antialias: true, preserveDrawingBuffer: true });  // readPixels below
renderer.setPixelRatio(window.devicePixelRatio || 1);
renderer.setSize(innerWidth, innerHeight);
$('view').appendChild(renderer.domElement);
const scene = new THREE.Scene();
scene.background = new THREE.Color(`rgb(${BG.join(',')})`);
const camera = new THREE.PerspectiveCamera(40, innerWidth / innerHeight, 0.01, 100);
camera.up.set(0, 0, 1);
const hemi = new THREE.HemisphereLight(0xffffff, 0x707880, 2.0);
hemi.position.set(0, 0, 1);
scene.add(hemi);
const sun = new THREE.DirectionalLight(0xffffff, 1.6);
sun.position.set(-1, -2, 3);
scene.add(sun);
const grid = new THREE.GridHelper(4, 16, 0xd4d7dc, 0xe4e6ea);
grid.rotation.x = Math.PI / 2;  // GridHelper lies in x-z; the world is z-up
scene.add(grid);

// ---- environment, target volume, placement regions
for (const o of D.env.objects) {
  const g = geometry(o.mesh);
  scene.add(new THREE.Mesh(g, glass(0x8a96a8, 0.3)));
  scene.add(new THREE.LineSegments(new THREE.EdgesGeometry(g, 25),
    new THREE.LineBasicMaterial({ color: 0x5a6678, transparent: true, opacity: 0.45 })));
}
const scan = f32(D.env.points);
if (scan.length) {
  const g = new THREE.BufferGeometry();
  g.setAttribute('position', new THREE.BufferAttribute(scan, 3));
  scene.add(new THREE.Points(g, new THREE.PointsMaterial({ color: 0x6a7688, size: 0.004 })));
}
const V = D.volume;
const volume = new THREE.Box3(new THREE.Vector3(V[0], V[1], V[2]), new THREE.Vector3(V[3], V[4], V[5]));
scene.add(new THREE.Box3Helper(volume, 0x1e6fd9));
const bestRegion = D.best ? D.best.region : -1;
D.regions.forEach((r, k) => {
  const color = new THREE.Color().setHSL((0.08 + 0.17 * k) % 1, 0.65, 0.55);
  scene.add(new THREE.Mesh(geometry(r.mesh), new THREE.MeshBasicMaterial({
    color, transparent: true, opacity: k === bestRegion ? 0.8 : 0.45, side: THREE.DoubleSide, depthWrite: false })));
});

// ---- robot links (one mesh per link, posed per frame)
const links = D.robot.meshes.map((m, k) => {
  const mesh = new THREE.Mesh(geometry(m), solid(k % 2 ? 0xd7dbe0 : 0xe39b4a));
  mesh.name = D.robot.names[k];
  scene.add(mesh);
  return mesh;
});

// ---- the object: initial (before regrasping), final (resting) and the carried one
const objectGeometry = geometry(D.object.mesh);
const carried = new THREE.Mesh(objectGeometry, solid(0x2f6fd0));
scene.add(carried);
const initial = new THREE.Mesh(objectGeometry, glass(0xe0a030, 0.4));
setPose(initial, D.object.initial);
if (D.solved) {
  scene.add(initial);
  const resting = new THREE.Mesh(objectGeometry, glass(0x2fb050, 0.45));
  setPose(resting, D.best.pose);
  scene.add(resting);
}
// Finger contact paths in the object frame: drawn on the initial object and on the carried one.
function fingerLines(points, color) {
  const g = new THREE.BufferGeometry().setFromPoints(points.map((p) => new THREE.Vector3(p[0], p[1], p[2])));
  const mat = { color, depthTest: false, transparent: true };
  const o = points.length > 1 ? new THREE.Line(g, new THREE.LineBasicMaterial(mat))
                              : new THREE.Points(g, new THREE.PointsMaterial({ ...mat, size: 0.006 }));
  o.renderOrder = 10;  // over the object, which they lie on
  return o;
}
for (const s of D.in_hand || []) {
  for (const [pts, color] of [[s.finger1, 0xd02828], [s.finger2, 0x9b30c0]]) {
    if (!pts.length) continue;
    initial.add(fingerLines(pts, color));
    carried.add(fingerLines(pts, color));
  }
}

// ---- motion
const M = D.motion;
const L = links.length;
const linkPoses = f32(M.links);
const objectPoses = f32(M.object);
const qa = new THREE.Quaternion(), qb = new THREE.Quaternion();
function blend(o, A, a0, b0, w) {
  o.position.set(A[a0] + w * (A[b0] - A[a0]), A[a0 + 1] + w * (A[b0 + 1] - A[a0 + 1]), A[a0 + 2] + w * (A[b0 + 2] - A[a0 + 2]));
  qa.set(A[a0 + 3], A[a0 + 4], A[a0 + 5], A[a0 + 6]);
  qb.set(A[b0 + 3], A[b0 + 4], A[b0 + 5], A[b0 + 6]);
  o.quaternion.copy(qa.slerp(qb, w));
}
// Frames carry their time (s, real time from the first push or the transport); t is a time.
const T = M.times, duration = T[T.length - 1] || 0;
function frameAt(t) {  // the last frame at or before t
  let lo = 0, hi = M.frames - 1;
  while (lo < hi) { const mid = (lo + hi + 1) >> 1; if (T[mid] <= t) lo = mid; else hi = mid - 1; }
  return lo;
}
function applyFrame(t) {
  const i = frameAt(t), j = Math.min(i + 1, M.frames - 1);
  const w = j > i && T[j] > T[i] ? Math.min(1, Math.max(0, (t - T[i]) / (T[j] - T[i]))) : 0;
  for (let l = 0; l < L; l++) blend(links[l], linkPoses, (i * L + l) * 7, (j * L + l) * 7, w);
  blend(carried, objectPoses, i * 7, j * 7, w);
}
function phaseText(t) {
  if (!D.solved) return 'start configuration (no solution)';
  const f = frameAt(t), clock = `${t.toFixed(2)} / ${duration.toFixed(2)} s · `;
  const P = D.path_waypoints, pushes = M.pushes.filter((p) => p <= f).length;
  if (pushes && f < M.waypoints[0]) return clock + `pusher: in-hand action ${pushes} / ${M.pushes.length}`;
  const wp = M.waypoints.filter((w) => w <= f).length;  // waypoints reached
  if (M.retreat < 0 || f < M.retreat) return clock + `path: waypoint ${Math.max(1, wp)} / ${P}`;
  return clock + `released; retreat: waypoint ${wp - P} / ${D.steps - P}`;
}

// ---- panel
const fmt = (v, d = 3) => v.map((x) => x.toFixed(d)).join(', ');
$('title').textContent = D.title;
$('summary').textContent = D.solved
  ? `objective ${D.best.objective.toFixed(4)}, found after ${D.best.time.toFixed(2)} s of ${D.seconds.toFixed(1)} s` +
    (D.variant ? ` (${D.variant})` : '')
  : `no solution after ${D.seconds.toFixed(1)} s`;
$('reason').textContent = D.solved ? '' : D.reason;
$('legend').innerHTML = (D.solved
  ? [['#e0a030', 'initial'], ['#2fb050', 'final'], ['#2f6fd0', 'carried'], ['#1e6fd9', 'volume'], ['#d02828', 'finger 1'],
     ['#9b30c0', 'finger 2']]
  : [['#2f6fd0', 'object'], ['#1e6fd9', 'volume']]).map(([c, n]) => `<i><span style="background:${c}"></span>${n}</i>`).join(' ');
if (D.solved) {
  const items = (D.in_hand || []).map((s) => s.type === 'push'
    ? `push ${(s.distance * 1000).toFixed(1)} mm along (${fmt(s.direction, 2)})`
    : `rotate ${(s.angle * 180 / Math.PI).toFixed(1)}° about (${fmt(s.axis, 2)}) at (${fmt(s.pivot.map((x) => x * 1000), 1)}) mm`);
  if (M.pushes.length) items.push(`the pusher performs the ${M.pushes.length} in-hand action(s) (the arm holds its start)`);
  items.push(`carry along ${D.path_waypoints} waypoints, release, retreat ${D.steps - D.path_waypoints}`);
  const ol = document.createElement('ol');
  for (const text of items) ol.appendChild(document.createElement('li')).textContent = text;
  $('inhand').textContent = D.in_hand.length ? 'in-hand sequence:' : 'no regrasp needed:';
  $('inhand').appendChild(ol);
}
function drawPlot() {
  const pts = D.improvements;
  if (!pts.length) return;
  const c = $('plot'), g = c.getContext('2d'), W = c.width, H = c.height, m = 34;
  c.hidden = false;
  const tmax = Math.max(D.seconds, pts[pts.length - 1][0]) || 1;
  let lo = Math.min(...pts.map((p) => p[1])), hi = Math.max(...pts.map((p) => p[1]));
  if (hi - lo < 1e-9) { lo -= 0.5 * Math.abs(lo) + 1e-3; hi += 0.5 * Math.abs(hi) + 1e-3; }
  const top = 22, bottom = H - 14;  // plot area rows; the title sits above, the time axis below
  const X = (t) => m + (W - m - 6) * t / tmax, Y = (v) => bottom - 4 - (bottom - top - 8) * (v - lo) / (hi - lo);
  g.font = '10px sans-serif';
  g.fillStyle = '#555';
  g.fillText('best objective over time (s)', m, 11);
  g.fillText(hi.toPrecision(3), 1, Y(hi) + 3);
  g.fillText(lo.toPrecision(3), 1, Y(lo) + 3);
  g.fillText('0', m, H - 3);
  g.fillText(tmax.toFixed(1), W - 24, H - 3);
  g.strokeStyle = '#bbb';
  g.strokeRect(m, top, W - m - 6, bottom - top);
  g.strokeStyle = '#1e6fd9';
  g.lineWidth = 2;
  g.beginPath();
  pts.forEach(([t, v], k) => {
    if (k === 0) g.moveTo(X(t), Y(v)); else { g.lineTo(X(t), Y(pts[k - 1][1])); g.lineTo(X(t), Y(v)); }
  });
  g.lineTo(X(tmax), Y(pts[pts.length - 1][1]));
  g.stroke();
}
drawPlot();

// ---- camera: the volume and the robot at its start, seen from behind-left of the robot
applyFrame(0);
const box = volume.clone();
for (const l of links) box.expandByObject(l);
const center = box.getCenter(new THREE.Vector3());
const radius = box.getBoundingSphere(new THREE.Sphere()).radius;
const dist = 1.1 * radius / Math.sin((camera.fov * Math.PI / 180) / 2);
camera.position.copy(center).addScaledVector(new THREE.Vector3(-0.55, -1, 0.65).normalize(), dist);
const controls = new OrbitControls(camera, renderer.domElement);
controls.target.copy(center);
controls.update();
addEventListener('resize', () => {
  camera.aspect = innerWidth / innerHeight;
  camera.updateProjectionMatrix();
  renderer.setSize(innerWidth, innerHeight);
});

// ---- playback
const slider = $('slider'), play = $('play'), status = $('dmgplace-status');
slider.max = String(duration);
let t = 0, playing = M.frames > 1, hold = 0, last = performance.now();
play.textContent = playing ? 'Pause' : 'Play';
play.disabled = M.frames <= 1;
slider.disabled = M.frames <= 1;
play.addEventListener('click', () => { playing = !playing; play.textContent = playing ? 'Pause' : 'Play'; });
slider.addEventListener('input', () => { t = Number(slider.value); playing = false; play.textContent = 'Play'; });
addEventListener('keydown', (e) => { if (e.key === ' ') { e.preventDefault(); play.click(); } });

// Share of canvas pixels that are not background: lets a headless test see that something was drawn.
function pixelStats() {
  const gl = renderer.getContext(), w = gl.drawingBufferWidth, h = gl.drawingBufferHeight;
  const px = new Uint8Array(w * h * 4);
  gl.readPixels(0, 0, w, h, gl.RGBA, gl.UNSIGNED_BYTE, px);
  let n = 0;
  for (let i = 0; i < px.length; i += 4)
    if (Math.abs(px[i] - BG[0]) + Math.abs(px[i + 1] - BG[1]) + Math.abs(px[i + 2] - BG[2]) > 12) n++;
  return { nonBackground: n, pixels: w * h };
}

const viewer = window.dmgplaceViewer;
viewer.steps = D.steps;
viewer.frames = M.frames;
viewer.pixelStats = pixelStats;
function frame(now) {
  const dt = Math.min(0.1, Math.max(0, (now - last) / 1000));
  last = now;
  if (playing) {
    if (t >= duration) {
      hold += dt;
      if (hold > 1.5) { t = 0; hold = 0; }
    } else {
      t = Math.min(duration, t + dt);
    }
    slider.value = String(t);
  }
  applyFrame(t);
  controls.update();
  renderer.render(scene, camera);
  viewer.rendered++;
  if (viewer.rendered === 1) {
    const s = pixelStats();
    viewer.nonBackground = s.nonBackground / s.pixels;
    status.dataset.nonbackground = viewer.nonBackground.toFixed(4);
    viewer.ready = true;
    status.dataset.ready = 'true';
    status.dataset.steps = String(D.steps);
  }
  status.dataset.rendered = String(viewer.rendered);
  status.textContent = `steps: ${D.steps} · frames drawn: ${viewer.rendered}`;
  $('phase').textContent = phaseText(t);
  requestAnimationFrame(frame);
}
requestAnimationFrame(frame);
