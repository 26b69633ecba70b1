// The mouse as the haptic device (pages opened with the session's token).
// A drag that starts on a link moves the device tip in 3-D: on the plane
// through the picked point facing the camera, the wheel moving that plane in
// depth. A plain drag pushes: the tip sphere starts just outside the picked
// surface and penetrates as the mouse (or the wheel) moves it in (eq. 3). A
// shift-drag pulls: the spring of eq. 4 from the picked point on the link to
// the cursor; holding Alt as well turns the grabbed frame instead (the 6-D
// pull: horizontal motion about the vertical, vertical motion about the
// screen's horizontal, ROTATE_PER_PIXEL rad a pixel; the scene's rotational
// spring, interaction.pull.k_rot, ties the link's orientation to it).
// Releasing parks the tip away from the robot. The page sends
// targets at most once per displayed frame; the haptic client smooths them
// at 1 kHz. A drag that starts off the robot orbits the view as usual.
import * as THREE from '/three/build/three.module.js';

export const WHEEL_STEP = 0.005;  // m per wheel notch
// A busy page gets coalesced wheel events whose deltas add up: count the
// notches in the delta, not the events, or a slow machine loses depth.
const PIXELS_PER_NOTCH = 100;  // Chromium's pixel delta for one notch
const LINES_PER_NOTCH = 3;  // Firefox reports lines
const CLEARANCE = 0.01;  // the tip starts this far outside the surface (the link may be moving), m
export const ROTATE_PER_PIXEL = 0.01;  // rad

// Signed notches in one wheel event: at least one, so a touchpad's small deltas still move.
export function wheelNotches(e) {
  const per = e.deltaMode === 1 ? LINES_PER_NOTCH : e.deltaMode === 2 ? 1 : PIXELS_PER_NOTCH;
  return Math.sign(e.deltaY) * Math.max(1, Math.round(Math.abs(e.deltaY) / per));
}

// The rotation vector (axis times angle, world) of a turn, a quaternion.
export function rotationVector(turn) {
  const q = turn.clone();
  if (q.w < 0) q.set(-q.x, -q.y, -q.z, -q.w);
  const s = Math.sqrt(q.x * q.x + q.y * q.y + q.z * q.z);
  if (s < 1e-12) return [0, 0, 0];
  const angle = 2 * Math.atan2(s, q.w);
  return [q.x / s * angle, q.y / s * angle, q.z / s * angle];
}

export class MouseDevice {
  constructor({ element, camera, controls, robot, send }) {
    this.element = element;
    this.camera = camera;
    this.controls = controls;
    this.robot = robot;
    this.send = send;
    this.enabled = false;
    this.drag = null;
    this.seq = 0;
    this.raycaster = new THREE.Raycaster();
    this.pending = null;
    // Capture phase: decide before OrbitControls whether a drag is ours.
    element.addEventListener('mousedown', (e) => this.down(e), true);
    window.addEventListener('mousemove', (e) => this.move(e), true);
    window.addEventListener('mouseup', (e) => this.up(e), true);
    element.addEventListener('wheel', (e) => this.wheel(e), { capture: true, passive: false });
  }

  ray(e) {
    const r = this.element.getBoundingClientRect();
    const ndc = new THREE.Vector2(((e.clientX - r.left) / r.width) * 2 - 1, -((e.clientY - r.top) / r.height) * 2 + 1);
    this.raycaster.setFromCamera(ndc, this.camera);
    return this.raycaster.ray;
  }

  // The link under the cursor: {link, point, normal} in world coordinates.
  pick(e) {
    this.ray(e);
    const hits = this.raycaster.intersectObjects(this.robot.pickables, false);
    const hit = hits.find((h) => h.object.userData.link !== undefined && h.face);
    if (!hit) return null;
    const normal = hit.face.normal.clone().transformDirection(hit.object.matrixWorld);
    const toCamera = this.camera.position.clone().sub(hit.point);
    if (normal.dot(toCamera) < 0) normal.negate();  // the side we look at
    return { link: hit.object.userData.link, point: hit.point.clone(), normal };
  }

  down(e) {
    if (!this.enabled || e.button !== 0) return;
    const picked = this.pick(e);
    if (!picked) return;  // off the robot: the view orbits
    e.stopPropagation();
    e.preventDefault();
    this.controls.enabled = false;
    const view = new THREE.Vector3();
    this.camera.getWorldDirection(view);
    const pull = e.shiftKey;
    const link = this.robot.links[picked.link];
    this.drag = {
      pull,
      link,
      view,
      origin: picked.point.clone(),
      depth: 0,
      // Push: the sphere's centre rides one radius (plus a little) off the surface.
      offset: pull ? new THREE.Vector3() : picked.normal.clone().multiplyScalar((this.robot.tipRadius || 0.01) + CLEARANCE),
      attachPoint: this.localPoint(link, picked.point),
      rotation: new THREE.Quaternion(),  // the grabbed frame's turn since the grab, world axes (Alt-drag)
      tip: picked.point.clone(),
    };
    this.target(picked.point, true);
  }

  localPoint(link, world) {
    const inverse = new THREE.Matrix4().getInverse(link.group.matrix);
    const p = world.clone().applyMatrix4(inverse);
    return [p.x, p.y, p.z];
  }

  // The tip for the cursor: on the camera-facing plane through the picked
  // point, moved `depth` along the view direction.
  cursorPoint(e) {
    const d = this.drag;
    const origin = d.origin.clone().addScaledVector(d.view, d.depth);
    const plane = new THREE.Plane().setFromNormalAndCoplanarPoint(d.view, origin);
    const out = new THREE.Vector3();
    return this.ray(e).intersectPlane(plane, out) ? out : origin;
  }

  move(e) {
    if (!this.drag) return;
    e.stopPropagation();
    const last = this.lastEvent;
    this.lastEvent = { clientX: e.clientX, clientY: e.clientY };
    if (this.drag.pull && e.altKey) {
      if (last) this.turn(e.clientX - last.clientX, e.clientY - last.clientY);
      this.target(this.drag.tip, false);  // the tip stays; the grabbed frame turns
      return;
    }
    this.target(this.cursorPoint(e), false);
  }

  // Alt-drag while pulling: dx turns about the vertical (z), dy about the camera's right axis.
  turn(dx, dy) {
    const right = new THREE.Vector3().setFromMatrixColumn(this.camera.matrixWorld, 0).normalize();
    const q = new THREE.Quaternion().setFromAxisAngle(new THREE.Vector3(0, 0, 1), dx * ROTATE_PER_PIXEL)
      .multiply(new THREE.Quaternion().setFromAxisAngle(right, dy * ROTATE_PER_PIXEL));
    this.drag.rotation.premultiply(q).normalize();
  }

  // The rotation vector of the grabbed frame's turn.
  rotationVector() { return rotationVector(this.drag.rotation); }

  wheel(e) {
    if (!this.drag) return;
    e.stopPropagation();
    e.preventDefault();
    this.drag.depth += wheelNotches(e) * WHEEL_STEP;  // away from you: deeper
    const at = this.lastEvent || e;
    this.target(this.cursorPoint(at), false);
  }

  up(e) {
    if (!this.drag) return;
    e.stopPropagation();
    this.drag = null;
    this.lastEvent = null;
    this.controls.enabled = true;
    this.pending = { type: 'device', tip: [0, 0, 0], active: false, pull: false };
  }

  target(point, jump) {
    const d = this.drag;
    d.tip = point.clone();
    const tip = point.clone().add(d.offset);
    const message = { type: 'device', tip: [tip.x, tip.y, tip.z], active: true, pull: d.pull };
    if (d.pull) {
      message.attach_link = d.link.name;
      message.attach_point = d.attachPoint;
      message.rotation = this.rotationVector();
    }
    // A jump (the start of a drag) must not be merged away.
    if (jump) {
      message.jump = true;
      this.flushMessage(message);
      this.jumpSent = { at: performance.now(), tip: message.tip };  // for the mouse-to-draw latency
    } else this.pending = message;
  }

  // Called once per displayed frame: the newest target goes out.
  flush() {
    if (this.pending) { this.flushMessage(this.pending); this.pending = null; }
  }

  flushMessage(message) {
    message.seq = ++this.seq;
    this.send(message);
  }
}
