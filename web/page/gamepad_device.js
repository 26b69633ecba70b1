// A gamepad or a 3-D mouse as the haptic device, read through the Gamepad API
// (and WebHID for a SpaceMouse, which Chromium does not show as a gamepad).
// Rate control in the camera's frame: a stick tilted moves the tip at up to
// SPEED m/s, past a dead zone. A cursor (a small sphere) shows where the tip
// is. Button 0 held (A; a 3-D mouse's left key): the tip jumps to the cursor,
// is live and pushes what it touches (eq. 3); released, it is parked. Button
// 1 held (B; the right key): a grab, the pull of eq. 4 from the link under
// the cursor, as a shift-click there; a 3-D mouse's rotation axes turn the
// grabbed frame meanwhile (the 6-D pull).
//
// Axes: a standard-mapping gamepad moves across the screen with the left
// stick (0: right, 1: down) and in depth with the right stick's vertical
// (3: toward you). A six-axis device (a 3-D mouse: tx ty tz rx ry rz) moves
// right with 0, into the screen with 1, down with 2, and turns with 3-5.
//
// The input layer reads an injectable source: window.igmsGamepadSource, a
// function returning gamepad-like objects ({id, mapping, axes, buttons:
// [{pressed}]}), is read before navigator.getGamepads(); tests script a pad
// with it.
import * as THREE from '/three/build/three.module.js';
import { rotationVector } from './mouse_device.js';

export const SPEED = 0.3;        // m/s at full tilt
export const TURN_SPEED = 1.5;   // rad/s at full twist (a 3-D mouse's rotation axes)
export const DEAD_ZONE = 0.12;   // of full tilt: a stick at rest reads a few per cent
const SPACEMOUSE_FULL = 350;     // a SpaceMouse report's full deflection (counts)

function shaped(a) {  // dead zone, then linear to full tilt
  const m = Math.abs(a);
  return m < DEAD_ZONE ? 0 : Math.sign(a) * Math.min(1, (m - DEAD_ZONE) / (1 - DEAD_ZONE));
}

// A SpaceMouse's WebHID input report as six axes (-1..1) and its buttons: report 1 is the
// translation (three little-endian int16), 2 the rotation, 3 the buttons (a bit each).
export function spaceMouseReport(state, reportId, bytes) {
  const axis = (k) => {
    const v = bytes[2 * k] | (bytes[2 * k + 1] << 8);
    return Math.max(-1, Math.min(1, (v >= 0x8000 ? v - 0x10000 : v) / SPACEMOUSE_FULL));
  };
  if (reportId === 1 && bytes.length >= 12) for (let k = 0; k < 6; k++) state.axes[k] = axis(k);  // newer: all six
  else if (reportId === 1 && bytes.length >= 6) for (let k = 0; k < 3; k++) state.axes[k] = axis(k);
  else if (reportId === 2 && bytes.length >= 6) for (let k = 0; k < 3; k++) state.axes[3 + k] = axis(k);
  else if (reportId === 3 && bytes.length >= 1) state.buttons = [0, 1].map((b) => ({ pressed: !!(bytes[0] & (1 << b)) }));
  return state;
}

export class GamepadDevice {
  constructor({ scene, camera, robot, send, busy }) {
    this.camera = camera;
    this.robot = robot;
    this.send = send;   // one message, in the page's device sequence
    this.busy = busy;   // true while the mouse drives the device: the pad waits
    this.enabled = false;
    this.cursor = null; // world, m; placed at the view's centre when a pad first shows
    this.active = false;
    this.grab = null;   // {link, attachPoint, rotation}
    this.lastPoll = null;
    this.hid = null;    // a SpaceMouse through WebHID: {id, mapping, axes, buttons}
    this.connected = '';
    this.marker = new THREE.Mesh(new THREE.SphereBufferGeometry(0.012, 16, 12),
                                 new THREE.MeshBasicMaterial({ color: 0xffcc33, wireframe: true }));
    this.marker.visible = false;
    scene.add(this.marker);
  }

  pads() {
    const source = window.igmsGamepadSource;
    const list = typeof source === 'function' ? source() :
      (navigator.getGamepads ? Array.from(navigator.getGamepads()) : []);
    const pads = (list || []).filter((p) => p && p.axes && p.axes.length >= 2);
    if (this.hid) pads.push(this.hid);
    return pads;
  }

  // WebHID: ask for a SpaceMouse (3Dconnexion's vendor id); its reports feed the same axes.
  async connectSpaceMouse() {
    if (!navigator.hid) throw new Error('this browser has no WebHID');
    const [dev] = await navigator.hid.requestDevice({ filters: [{ vendorId: 0x256f }, { vendorId: 0x046d, usagePage: 1, usage: 8 }] });
    if (!dev) return false;
    await dev.open();
    const state = { id: dev.productName + ' (WebHID)', mapping: 'spacemouse', axes: [0, 0, 0, 0, 0, 0], buttons: [] };
    dev.addEventListener('inputreport', (e) => spaceMouseReport(state, e.reportId, new Uint8Array(e.data.buffer)));
    this.hid = state;
    return true;
  }

  // Camera axes in the world: right, up, into the screen.
  frame() {
    const right = new THREE.Vector3().setFromMatrixColumn(this.camera.matrixWorld, 0).normalize();
    const up = new THREE.Vector3().setFromMatrixColumn(this.camera.matrixWorld, 1).normalize();
    const into = new THREE.Vector3();
    this.camera.getWorldDirection(into);
    return { right, up, into };
  }

  // Called once per displayed frame (`now`: ms).
  poll(now, home) {
    const dt = this.lastPoll === null ? 0 : Math.min(0.1, (now - this.lastPoll) / 1000);
    this.lastPoll = now;
    const pad = this.pads()[0];
    this.connected = pad ? String(pad.id || 'gamepad') : '';
    this.marker.visible = !!pad;
    if (!pad || !this.enabled) return;
    if (!this.cursor) this.cursor = home.clone();
    const a = (k) => shaped(Number(pad.axes[k]) || 0);
    const pressed = (k) => !!(pad.buttons && pad.buttons[k] && (pad.buttons[k].pressed || pad.buttons[k] === 1));
    const sixAxis = pad.mapping !== 'standard' && pad.axes.length >= 6;
    const { right, up, into } = this.frame();
    const v = sixAxis ? right.clone().multiplyScalar(a(0)).addScaledVector(into, a(1)).addScaledVector(up, -a(2))
                      : right.clone().multiplyScalar(a(0)).addScaledVector(up, -a(1)).addScaledVector(into, -a(3));
    this.cursor.addScaledVector(v, SPEED * dt);
    this.marker.position.copy(this.cursor);
    if (this.busy()) return;
    const grabbing = pressed(1), live = pressed(0) || grabbing;
    if (grabbing && !this.grab) this.grab = this.pick() || { none: true };
    if (!grabbing) this.grab = null;
    if (this.grab && !this.grab.none && sixAxis) {  // the grabbed frame turns with the device's twist
      const w = right.clone().multiplyScalar(a(3)).addScaledVector(into, a(4)).addScaledVector(up, -a(5));
      const angle = w.length() * TURN_SPEED * dt;
      if (angle > 0) this.grab.rotation.premultiply(new THREE.Quaternion().setFromAxisAngle(w.normalize(), angle));
    }
    if (live) {
      const m = { type: 'device', tip: this.cursor.toArray(), active: true, pull: !!(this.grab && !this.grab.none) };
      // A press starts a drag where the cursor is, as a click does where it picks: without the jump the
      // tip would come from where it was parked, along a line the person never steered.
      if (!this.active) m.jump = true;
      if (m.pull) {
        m.attach_link = this.grab.link.name;
        m.attach_point = this.grab.attachPoint;
        m.rotation = rotationVector(this.grab.rotation);
      }
      this.send(m);
    } else if (this.active) {
      this.send({ type: 'device', tip: [0, 0, 0], active: false, pull: false });
    }
    this.active = live;
  }

  // The link under the cursor, as the camera sees it: a ray from the eye through the cursor.
  pick() {
    const dir = this.cursor.clone().sub(this.camera.position).normalize();
    const hit = new THREE.Raycaster(this.camera.position.clone(), dir).intersectObjects(this.robot.pickables, false)
      .find((h) => h.object.userData.link !== undefined);
    if (!hit || hit.distance > this.cursor.distanceTo(this.camera.position) + 0.05) return null;
    const link = this.robot.links[hit.object.userData.link];
    const p = hit.point.clone().applyMatrix4(new THREE.Matrix4().getInverse(link.group.matrix));
    return { link, attachPoint: [p.x, p.y, p.z], rotation: new THREE.Quaternion() };
  }
}
