// The environment's contacts drawn over the scene: a dot at each contact
// point and an arrow for the force on side b (1 cm per newton, as the
// interaction's arrow), from the frame's "contacts" ({p, f}: flat x y z
// arrays). One Points and one LineSegments object whatever the count, so a
// pile of spheres costs two draw calls. `visible` toggles it (key c).
import * as THREE from '/three/build/three.module.js';
import { NEWTONS_TO_METRES } from './robot_view.js';

const MAX_CONTACTS = 4096;       // what the viewer forwards at most
const MAX_ARROW_METRES = 0.5;    // a very large force is drawn this long
const MIN_FORCE_N = 1e-3;        // below this a contact gets its dot only
const HEAD = 0.25;               // arrowhead: this fraction of the arrow, at most 2 cm
const UNIT_X = new THREE.Vector3(1, 0, 0), UNIT_Z = new THREE.Vector3(0, 0, 1);

export class ContactView {
  constructor(scene) {
    const points = new THREE.BufferGeometry();
    points.setAttribute('position', new THREE.Float32BufferAttribute(new Float32Array(3 * MAX_CONTACTS), 3));
    points.setDrawRange(0, 0);
    this.points = new THREE.Points(points, new THREE.PointsMaterial({ color: 0xffeb3b, size: 6, sizeAttenuation: false,
                                                                       depthTest: false }));
    // Three segments an arrow: the shaft and a two-stroke head.
    const lines = new THREE.BufferGeometry();
    lines.setAttribute('position', new THREE.Float32BufferAttribute(new Float32Array(18 * MAX_CONTACTS), 3));
    lines.setDrawRange(0, 0);
    this.arrows = new THREE.LineSegments(lines, new THREE.LineBasicMaterial({ color: 0xff7043, depthTest: false }));
    for (const o of [this.points, this.arrows]) {
      o.frustumCulled = false;
      o.renderOrder = 9;
      scene.add(o);
    }
    this.visible = true;
    this.count = 0;      // contacts drawn in the last update
    this.total = 0;      // contacts in that frame's step (more than drawn when the server sent 512 of them)
    this.arrowCount = 0; // of which with an arrow
  }

  setVisible(on) {
    this.visible = on;
    this.points.visible = on;
    this.arrows.visible = on;
  }

  update(frame) {
    const c = frame.contacts;
    const n = c && Array.isArray(c.p) && Array.isArray(c.f) ? Math.min(c.p.length, c.f.length, 3 * MAX_CONTACTS) / 3 | 0 : 0;
    const p = this.points.geometry.attributes.position;
    const a = this.arrows.geometry.attributes.position;
    let arrows = 0;
    const side = new THREE.Vector3(), dir = new THREE.Vector3();
    for (let k = 0; k < n; ++k) {
      const x = c.p[3 * k], y = c.p[3 * k + 1], z = c.p[3 * k + 2];
      p.setXYZ(k, x, y, z);
      const fx = c.f[3 * k], fy = c.f[3 * k + 1], fz = c.f[3 * k + 2];
      const f = Math.hypot(fx, fy, fz);
      if (!(f > MIN_FORCE_N)) continue;
      const length = Math.min(f * NEWTONS_TO_METRES, MAX_ARROW_METRES);
      dir.set(fx / f, fy / f, fz / f);
      const ex = x + dir.x * length, ey = y + dir.y * length, ez = z + dir.z * length;
      side.crossVectors(dir, Math.abs(dir.z) > 0.9 ? UNIT_X : UNIT_Z).normalize();
      const h = Math.min(HEAD * length, 0.02);
      const b = 6 * arrows;
      a.setXYZ(b, x, y, z);
      a.setXYZ(b + 1, ex, ey, ez);
      a.setXYZ(b + 2, ex, ey, ez);
      a.setXYZ(b + 3, ex - dir.x * h + side.x * 0.5 * h, ey - dir.y * h + side.y * 0.5 * h, ez - dir.z * h + side.z * 0.5 * h);
      a.setXYZ(b + 4, ex, ey, ez);
      a.setXYZ(b + 5, ex - dir.x * h - side.x * 0.5 * h, ey - dir.y * h - side.y * 0.5 * h, ez - dir.z * h - side.z * 0.5 * h);
      ++arrows;
    }
    // Upload only the part in use (the buffers hold MAX_CONTACTS: a full upload every frame
    // cost a software renderer a third of its frame rate on the 216-sphere pile).
    p.updateRange.offset = 0;
    p.updateRange.count = 3 * n;
    p.needsUpdate = true;
    a.updateRange.offset = 0;
    a.updateRange.count = 18 * arrows;
    a.needsUpdate = true;
    this.points.geometry.setDrawRange(0, n);
    this.arrows.geometry.setDrawRange(0, 6 * arrows);
    this.count = n;
    this.arrowCount = arrows;
    this.total = c ? c.total : 0;
  }
}
