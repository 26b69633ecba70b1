// The igms live view: connects to the igms process's WebSocket, builds the
// scene from its hello, and draws the newest frame at display rate. With
// the session's token in the URL the page is also the haptic device.
//
// window.igms exposes the page's state for tests and for the curious:
// the last frame and hello, frames drawn, the drawn link positions, the
// contacts drawn, and screen points on a link (to script a mouse drag).
import * as THREE from '/three/build/three.module.js';
import { OrbitControls } from '/three/examples/jsm/controls/OrbitControls.js';
import { RobotView } from './robot_view.js';
import { ContactView } from './contact_view.js';
import { Hud } from './hud.js';
import { MouseDevice } from './mouse_device.js';
import { GamepadDevice, spaceMouseReport } from './gamepad_device.js';
import { Timeline } from './timeline.js';

const container = document.getElementById('view');
// Multisampling costs a software renderer (SwiftShader: headless Chromium, no GPU) a third of
// its frame rate; a GPU does it for free.
function softwareWebGL() {
  const gl = document.createElement('canvas').getContext('webgl');
  const info = gl && gl.getExtension('WEBGL_debug_renderer_info');
  return !gl || (info && /SwiftShader|llvmpipe|Software/i.test(gl.getParameter(info.UNMASKED_RENDERER_WEBGL)));
}
const SOFTWARE = softwareWebGL();
const renderer = new THREE.WebGLRenderer({ antialias: !SOFTWARE, preserveDrawingBuffer: true });
renderer.setPixelRatio(window.devicePixelRatio);
renderer.setSize(window.innerWidth, window.innerHeight);
container.appendChild(renderer.domElement);

const scene = new THREE.Scene();
scene.background = new THREE.Color(0x1d2229);
scene.add(new THREE.HemisphereLight(0xffffff, 0x445566, 0.9));
const sun = new THREE.DirectionalLight(0xffffff, 0.7);
sun.position.set(2, -3, 4);
scene.add(sun);
const grid = new THREE.GridHelper(4, 40, 0x4a5560, 0x333b44);
grid.rotation.x = Math.PI / 2;  // the floor is z = 0
scene.add(grid);
scene.add(new THREE.AxesHelper(0.2));

const camera = new THREE.PerspectiveCamera(45, window.innerWidth / window.innerHeight, 0.01, 100);
camera.up.set(0, 0, 1);
const HOME = { position: new THREE.Vector3(1.8, -1.9, 1.3), target: new THREE.Vector3(0.1, 0, 0.4) };
camera.position.copy(HOME.position);
const controls = new OrbitControls(camera, renderer.domElement);
controls.target.copy(HOME.target);
controls.update();

function resetView() {
  camera.position.copy(HOME.position);
  controls.target.copy(HOME.target);
  controls.update();
}

// Home is where the whole scene fits: set from the first frame of a session.
function fitView() {
  const box = new THREE.Box3();
  for (const link of robot.links) box.expandByObject(link.group);  // the robot, not the walls
  if (box.isEmpty()) return;
  const centre = box.getCenter(new THREE.Vector3());
  const size = Math.max(box.getSize(new THREE.Vector3()).length(), 0.3);
  HOME.target.copy(centre);
  HOME.position.copy(centre).add(new THREE.Vector3(1.0, -1.1, 0.75).multiplyScalar(size));
  resetView();
}

window.addEventListener('resize', () => {
  camera.aspect = window.innerWidth / window.innerHeight;
  camera.updateProjectionMatrix();
  renderer.setSize(window.innerWidth, window.innerHeight);
});

const robot = new RobotView(scene, { software: SOFTWARE });
const contacts = new ContactView(scene);
const hud = new Hud();
const params = new URLSearchParams(window.location.search);
// The token rides in the URL's fragment (#token=...), which the browser never sends to a server.
const token = new URLSearchParams(window.location.hash.slice(1)).get('token');
// Another token in the same tab (a new session's URL pasted in): a browser does not reload for a
// fragment, so the page does, and connects with it.
window.addEventListener('hashchange', () => window.location.reload());

let socket = null;
function send(message) {
  if (socket && socket.readyState === WebSocket.OPEN) socket.send(JSON.stringify(message));
}

const device = new MouseDevice({ element: renderer.domElement, camera, controls, robot, send });
// A gamepad or 3-D mouse drives the same device, in the same message sequence, while the mouse does not.
const gamepad = new GamepadDevice({ scene, camera, robot, send: (m) => device.flushMessage(m), busy: () => !!device.drag });
const timeline = new Timeline(send);

const state = {
  role: null, hello: null, frame: null, framesReceived: 0, framesDrawn: 0, helloCount: 0,
  fps: 0, connected: false, maxForce: 0, maxOffNominal: 0, software: SOFTWARE, renderScale: 1,
};

function command(kind, extra) {
  if (state.role !== 'device') return;
  send(Object.assign({ type: 'command', kind }, extra || {}));
  hud.notice(kind === 'save' ? 'saving the edited trajectory (the server writes it in its folder)' : kind);
}

function togglePause() {
  const paused = state.frame && state.frame.server && state.frame.server.state === 'paused';
  command(paused ? 'resume' : 'pause');
}

document.getElementById('reset-view').addEventListener('click', resetView);
document.getElementById('pause').addEventListener('click', togglePause);
document.getElementById('step').addEventListener('click', () => command('step'));
document.getElementById('reset').addEventListener('click', () => command('reset'));
document.getElementById('save').addEventListener('click', () => command('save', { file: 'edited_trajectory.yaml' }));
// A SpaceMouse over WebHID (Chromium shows it as no gamepad): the browser asks which device.
document.getElementById('spacemouse').hidden = !navigator.hid;
document.getElementById('spacemouse').addEventListener('click', () => {
  gamepad.connectSpaceMouse().then((ok) => hud.notice(ok ? '3-D mouse connected' : 'no 3-D mouse chosen'))
    .catch((e) => hud.notice('3-D mouse: ' + e.message));
});
window.addEventListener('keydown', (e) => {
  if (e.target instanceof HTMLInputElement || e.target instanceof HTMLSelectElement) return;
  if (e.key === 'v') resetView();
  else if (e.key === ' ') { e.preventDefault(); togglePause(); }
  else if (e.key === 's') command('step');
  else if (e.key === 'r') command('reset');
  else if (e.key === 'w') command('save', { file: 'edited_trajectory.yaml' });
  else if (e.key === 'c') { contacts.setVisible(!contacts.visible); hud.notice('contacts ' + (contacts.visible ? 'shown' : 'hidden')); }
});

function onMessage(text) {
  let m;
  try { m = JSON.parse(text); } catch (e) { return; }
  if (m.type === 'welcome') {
    state.role = m.role;
    hud.role(m.role);
    device.enabled = m.role === 'device';
    gamepad.enabled = m.role === 'device';
  } else if (m.type === 'hello') {
    state.hello = m;
    state.helloCount++;
    robot.build(m);
    hud.hello(m);
    state.fitPending = state.helloCount === 1;  // later sessions keep the user's view
    state.maxForce = 0;
    state.maxOffNominal = 0;
  } else if (m.type === 'frame') {
    state.frame = m;
    state.framesReceived++;
    state.frameDirty = true;
  }
}

function connect() {
  const url = (location.protocol === 'https:' ? 'wss://' : 'ws://') + location.host + '/ws';
  socket = new WebSocket(url);
  socket.onopen = () => {
    // The token goes as the socket's first message, never in a URL (server logs, history, process lists).
    if (token) socket.send(JSON.stringify({type: 'auth', token: token}));
    state.connected = true;
    hud.connection(true);
  };
  socket.onmessage = (event) => onMessage(event.data);
  socket.onclose = () => {
    state.connected = false;
    hud.connection(false);
    setTimeout(connect, 1000);
  };
}
connect();

// Figures a person (or a test) may want: how far the traced link is from
// the nominal path now, the largest contact force seen.
function track(frame) {
  const force = frame.force ? Math.hypot(...frame.force) : 0;
  state.maxForce = Math.max(state.maxForce, force);
  if (frame.device) state.maxDeviceForce = Math.max(state.maxDeviceForce || 0, Math.hypot(...frame.device.force));
  if (robot.traced >= 0 && frame.poses && frame.poses[robot.traced] && frame.t !== undefined) {
    const nominal = robot.nominalAt(frame.t);
    if (nominal) {
      const x = frame.poses[robot.traced];
      state.offNominal = Math.hypot(x[0] - nominal[0], x[1] - nominal[1], x[2] - nominal[2]);
      state.maxOffNominal = Math.max(state.maxOffNominal, state.offNominal);
    }
  }
}

// A software renderer that cannot keep 30 frames a second draws at half the
// resolution (a quarter of the pixels to shade) rather than drop frames:
// decided once a session, after two slow seconds in a row.
const MIN_FPS = 30;
let slowSeconds = 0;
// ?resolution=full keeps the full resolution (screenshots).
const FULL_RESOLUTION = params.get('resolution') === 'full';
function adaptResolution() {
  if (!SOFTWARE || FULL_RESOLUTION || state.renderScale < 1) return;
  slowSeconds = state.fps < MIN_FPS ? slowSeconds + 1 : 0;
  if (slowSeconds < 2) return;
  state.renderScale = 0.5;
  renderer.setPixelRatio(0.5 * window.devicePixelRatio);
  hud.notice('software rendering below ' + MIN_FPS + ' fps: drawing at half resolution');
}

let fpsCount = 0, fpsStart = performance.now();
function animate(now) {
  requestAnimationFrame(animate);
  if (state.frameDirty) {
    state.frameDirty = false;
    const f = state.frame;
    robot.update(f);
    contacts.update(f);
    if (state.fitPending) { state.fitPending = false; robot.root.updateMatrixWorld(true); fitView(); }
    hud.frame(f);
    track(f);
    if (f.timeline) timeline.update(f.timeline);
    // Mouse to drawn reaction: the first frame whose device tip is where the drag began.
    if (device.jumpSent && f.device && f.device.active) {
      const a = device.jumpSent.tip, b = f.device.tip;
      if (Math.hypot(a[0] - b[0], a[1] - b[1], a[2] - b[2]) < 2e-3) {
        state.mouseToDrawMs = now - device.jumpSent.at;
        device.jumpSent = null;
      }
    }
    state.drawnSeq = f.seq;
    state.drawnTime = f.t;
  }
  if (robot.meshesPending === 0 && robot.missingMeshes.length) hud.missingMeshes(robot.missingMeshes);
  device.flush();
  gamepad.poll(now, controls.target);
  if (gamepad.connected !== state.gamepad) { state.gamepad = gamepad.connected; hud.gamepad(gamepad.connected); }
  renderer.render(scene, camera);
  state.framesDrawn++;
  fpsCount++;
  if (now - fpsStart >= 1000) {
    state.fps = (1000 * fpsCount) / (now - fpsStart);
    fpsCount = 0;
    fpsStart = now;
    adaptResolution();
  }
}
requestAnimationFrame(animate);

// Client pixel coordinates of a world point.
function screenOf(p) {
  const v = new THREE.Vector3(p[0], p[1], p[2]).project(camera);
  const r = renderer.domElement.getBoundingClientRect();
  return { x: r.left + ((v.x + 1) / 2) * r.width, y: r.top + ((1 - v.y) / 2) * r.height, visible: v.z < 1 };
}

// A screen point where `link` is the nearest thing under the cursor, its
// surface facing the camera most squarely (so a push into the screen goes
// into the link): scanned over the link's projected bounding box.
function pointOnLink(index) {
  const link = robot.links[index];
  if (!link) return null;
  const box = new THREE.Box3().setFromObject(link.group);
  if (box.isEmpty()) return null;
  let x0 = Infinity, y0 = Infinity, x1 = -Infinity, y1 = -Infinity;
  for (let k = 0; k < 8; k++) {
    const c = screenOf([k & 1 ? box.max.x : box.min.x, k & 2 ? box.max.y : box.min.y, k & 4 ? box.max.z : box.min.z]);
    x0 = Math.min(x0, c.x); x1 = Math.max(x1, c.x); y0 = Math.min(y0, c.y); y1 = Math.max(y1, c.y);
  }
  const r = renderer.domElement.getBoundingClientRect();
  x0 = Math.max(x0, r.left); y0 = Math.max(y0, r.top); x1 = Math.min(x1, r.right - 1); y1 = Math.min(y1, r.bottom - 1);
  const step = Math.max(2, Math.round(Math.max(x1 - x0, y1 - y0) / 60));
  const raycaster = new THREE.Raycaster();
  let best = null;
  for (let y = y0; y <= y1; y += step) {
    for (let x = x0; x <= x1; x += step) {
      raycaster.setFromCamera(new THREE.Vector2(((x - r.left) / r.width) * 2 - 1, -((y - r.top) / r.height) * 2 + 1), camera);
      const hit = raycaster.intersectObjects(robot.pickables, false)[0];
      if (!hit || hit.object.userData.link !== index || !hit.face) continue;
      const normal = hit.face.normal.clone().transformDirection(hit.object.matrixWorld);
      const facing = -normal.dot(raycaster.ray.direction);
      if (!best || facing > best.facing) best = { x: Math.round(x), y: Math.round(y), point: hit.point.toArray(), facing };
    }
  }
  return best;
}

window.igms = {
  THREE,
  renderer,
  state,
  send: (message) => socket && socket.readyState === WebSocket.OPEN && socket.send(message),
  robot,
  contacts,
  device,
  gamepad,
  spaceMouseReport,
  camera,
  resetView,
  screenOf,
  pointOnLink,
  linkIndex: (name) => robot.linkIndex(name),
  linkPosition: (i) => robot.linkPosition(i),
  linkQuaternion: (i) => robot.linkQuaternion(i),
};
