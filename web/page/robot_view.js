// The session drawn in three.js: links from the URDF's visual geometry (or
// the collision geometry, or a stick to the parent link when a link has
// neither), the scene's obstacles, the nominal and the executed path of the
// traced link, the device tip, the contact force as an arrow scaled in
// newtons, the pull spring as a line, and links in collision highlighted.
// The world is z-up, as in the URDF.
import * as THREE from '/three/build/three.module.js';
import { STLLoader } from '/three/examples/jsm/loaders/STLLoader.js';
import { ColladaLoader } from '/three/examples/jsm/loaders/ColladaLoader.js';
import { OBJLoader } from '/three/examples/jsm/loaders/OBJLoader.js';

export const NEWTONS_TO_METRES = 0.01;  // force arrows: 1 cm per newton
const MAX_PATH_POINTS = 20000;
const COLLISION_COLOUR = new THREE.Color(0xff1744);
const NO_GLOW = new THREE.Color(0);

function toColour(rgba, fallback) {
  return rgba ? new THREE.Color(rgba[0], rgba[1], rgba[2]) : new THREE.Color(fallback);
}

// Places an object by the hello's {p, q} (q as w x y z).
function place(object, shape) {
  object.position.set(shape.p[0], shape.p[1], shape.p[2]);
  object.quaternion.set(shape.q[1], shape.q[2], shape.q[3], shape.q[0]);
}

// A kind the page has no form of (a capsule; any kind added later), as the
// server's triangles of its surface (core/geometry/shape_surface.h).
function surfaceGeometry(surface) {
  const g = new THREE.BufferGeometry();
  g.setAttribute('position', new THREE.Float32BufferAttribute(surface.vertices, 3));
  g.setIndex(surface.triangles);
  g.computeVertexNormals();
  return g;
}

function primitive(shape) {
  if (shape.surface) return surfaceGeometry(shape.surface);
  switch (shape.kind) {
    case 'box': return new THREE.BoxBufferGeometry(shape.size[0], shape.size[1], shape.size[2]);
    case 'sphere': return new THREE.SphereBufferGeometry(shape.size[0], 24, 16);
    case 'cylinder': {
      // URDF cylinders lie along z; three.js's along y.
      const g = new THREE.CylinderBufferGeometry(shape.size[0], shape.size[0], shape.size[1], 24);
      g.rotateX(Math.PI / 2);
      return g;
    }
    // The ground: 20 m square of its z = 0 plane (three.js's plane lies in x y, facing +z).
    case 'plane': return new THREE.PlaneBufferGeometry(20, 20);
  }
  return null;
}

// Many free bodies (a pile): coarser spheres, so a software renderer keeps its frame rate.
const MANY_BODIES = 50;

export class RobotView {
  // software: the page renders without a GPU (free bodies then get the cheaper Lambert shading).
  constructor(scene, { software = false } = {}) {
    this.scene = scene;
    this.software = software;
    this.root = new THREE.Group();
    scene.add(this.root);
    this.links = [];          // per link: {name, group, materials, pickables}
    this.pickables = [];      // meshes a drag can start on
    this.meshesPending = 0;
    this.missingMeshes = [];
    this.traced = -1;
    this.stlLoader = new STLLoader();
    this.colladaLoader = new ColladaLoader();
    this.objLoader = new OBJLoader();
    this.makeOverlays();
  }

  makeOverlays() {
    const s = this.scene;
    // The interaction is drawn over everything: a push on the far side of a link stays visible.
    const onTop = (object) => {
      object.renderOrder = 10;
      object.traverse((c) => { if (c.material) c.material.depthTest = false; });
      return object;
    };
    this.tip = new THREE.Mesh(new THREE.SphereBufferGeometry(1, 20, 14),
                              new THREE.MeshStandardMaterial({ color: 0xffa000, transparent: true, opacity: 0.9 }));
    this.tip.visible = false;
    s.add(onTop(this.tip));
    this.arrow = new THREE.ArrowHelper(new THREE.Vector3(0, 0, 1), new THREE.Vector3(), 0.1, 0xff5252, 0.03, 0.02);
    this.arrow.visible = false;
    s.add(onTop(this.arrow));
    this.deviceArrow = new THREE.ArrowHelper(new THREE.Vector3(0, 0, 1), new THREE.Vector3(), 0.1, 0x40c4ff, 0.03, 0.02);
    this.deviceArrow.visible = false;
    s.add(onTop(this.deviceArrow));
    this.contact = new THREE.Mesh(new THREE.SphereBufferGeometry(0.006, 12, 8),
                                  new THREE.MeshBasicMaterial({ color: 0xffeb3b }));
    this.contact.visible = false;
    s.add(onTop(this.contact));
    const springGeometry = new THREE.BufferGeometry();
    springGeometry.setAttribute('position', new THREE.Float32BufferAttribute(new Float32Array(6), 3));
    this.spring = new THREE.Line(springGeometry, new THREE.LineBasicMaterial({ color: 0x69f0ae }));
    this.spring.visible = false;
    this.spring.frustumCulled = false;
    s.add(onTop(this.spring));
    const executed = new THREE.BufferGeometry();
    executed.setAttribute('position', new THREE.Float32BufferAttribute(new Float32Array(3 * MAX_PATH_POINTS), 3));
    executed.setDrawRange(0, 0);
    this.executed = new THREE.Line(executed, new THREE.LineBasicMaterial({ color: 0xff9800 }));
    this.executed.frustumCulled = false;
    s.add(this.executed);
    this.executedCount = 0;
    this.nominal = null;
  }

  clear() {
    this.scene.remove(this.root);
    this.root = new THREE.Group();
    this.scene.add(this.root);
    this.links = [];
    this.pickables = [];
    this.missingMeshes = [];
    if (this.nominal) this.scene.remove(this.nominal);
    this.nominal = null;
    this.clearExecuted();
  }

  clearExecuted() {
    this.executedCount = 0;
    this.executed.geometry.setDrawRange(0, 0);
  }

  // Builds everything the hello message describes.
  build(hello) {
    this.clear();
    this.hello = hello;
    this.traced = hello.traced_link ?? -1;
    this.tipRadius = hello.push ? hello.push.tip_radius : 0.01;
    // Free bodies of one shape and colour share one geometry and one material (a pile is
    // hundreds of the same sphere).
    this.shared = new Map();
    this.manyBodies = hello.links.filter((l) => l.free_body).length > MANY_BODIES;
    hello.links.forEach((link, index) => this.links.push(this.buildLink(link, index)));
    // Sticks wherever a link has no geometry of its own: parent origin to link origin.
    this.sticks = [];
    hello.links.forEach((link, index) => {
      if (link.geometry === 'none' && link.parent >= 0) this.sticks.push([link.parent, index]);
    });
    if (this.sticks.length) {
      const g = new THREE.BufferGeometry();
      g.setAttribute('position', new THREE.Float32BufferAttribute(new Float32Array(6 * this.sticks.length), 3));
      this.stickLines = new THREE.LineSegments(g, new THREE.LineBasicMaterial({ color: 0xb0bec5 }));
      this.stickLines.frustumCulled = false;
      this.root.add(this.stickLines);
    } else {
      this.stickLines = null;
    }
    for (const o of hello.obstacles) {
      // Ghosts (only monitored) are see-through; solid obstacles and the ground are not. The
      // ground fills most of the screen: a software renderer shades it per vertex (Lambert),
      // which costs it a fraction of the per-pixel shading.
      const object = o.kind === 'plane' && this.software
        ? new THREE.Mesh(primitive(o), new THREE.MeshLambertMaterial({ color: 0x78909c }))
        : this.buildShape(o, o.kind === 'plane' ? 0x78909c : 0x90a4ae, null);
      if (object.isMesh) place(object, o);
      object.traverse((c) => {
        if (c.material && !o.solid) { c.material.transparent = true; c.material.opacity = 0.55; }
        if (c.material && o.kind === 'plane') c.material.side = THREE.DoubleSide;
      });
      object.name = 'obstacle:' + o.name;
      this.root.add(object);
    }
    if (hello.nominal_path && hello.nominal_path.length > 1) {
      const points = hello.nominal_path.map((p) => new THREE.Vector3(p[0], p[1], p[2]));
      this.nominal = new THREE.Line(new THREE.BufferGeometry().setFromPoints(points),
                                    new THREE.LineDashedMaterial({ color: 0x80deea, dashSize: 0.02, gapSize: 0.01 }));
      this.nominal.computeLineDistances();
      this.scene.add(this.nominal);
    }
  }

  buildLink(link, index) {
    const group = new THREE.Group();
    group.name = link.name;
    group.matrixAutoUpdate = false;
    const entry = { name: link.name, group, materials: [], index };
    for (const shape of link.shapes) {
      const colour = link.geometry === 'collision' ? 0xb0bec5 : 0xcfd8dc;
      const object = link.free_body && shape.kind !== 'mesh' ? this.buildSharedShape(shape, colour, entry)
                                                               : this.buildShape(shape, colour, entry);
      group.add(object);
    }
    this.root.add(group);
    return entry;
  }

  // A free body's primitive: geometry and material shared with every body of
  // the same shape and colour (its material is not highlighted on collision).
  buildSharedShape(shape, fallbackColour, entry) {
    const key = JSON.stringify([shape.kind, shape.size, shape.rgba || fallbackColour]);
    let parts = this.shared.get(key);
    if (!parts) {
      const colour = toColour(shape.rgba, fallbackColour);
      const material = this.software ? new THREE.MeshLambertMaterial({ color: colour })
                                     : new THREE.MeshStandardMaterial({ color: colour, metalness: 0.1, roughness: 0.7 });
      if (shape.rgba && shape.rgba[3] < 1) { material.transparent = true; material.opacity = shape.rgba[3]; }
      const geometry = shape.kind === 'sphere' && this.manyBodies
        ? new THREE.SphereBufferGeometry(shape.size[0], 12, 8) : primitive(shape);
      parts = { geometry, material };
      this.shared.set(key, parts);
    }
    const holder = new THREE.Group();
    place(holder, shape);
    const mesh = new THREE.Mesh(parts.geometry, parts.material);
    mesh.userData.link = entry.index;
    this.pickables.push(mesh);
    holder.add(mesh);
    return holder;
  }

  // One shape in its parent's frame. Meshes load asynchronously into a group
  // that is already placed.
  buildShape(shape, fallbackColour, entry) {
    const material = new THREE.MeshStandardMaterial({ color: toColour(shape.rgba, fallbackColour),
                                                      metalness: 0.1, roughness: 0.7 });
    if (shape.rgba && shape.rgba[3] < 1) { material.transparent = true; material.opacity = shape.rgba[3]; }
    if (entry) entry.materials.push(material);
    const holder = new THREE.Group();
    place(holder, shape);
    const addMesh = (geometry, m) => {
      const mesh = new THREE.Mesh(geometry, m);
      if (entry) { mesh.userData.link = entry.index; this.pickables.push(mesh); }
      return mesh;
    };
    if (shape.kind !== 'mesh') {
      holder.add(addMesh(primitive(shape), material));
      return holder;
    }
    if (shape.missing) {
      this.missingMeshes.push(shape.missing);
      return holder;
    }
    holder.scale.set(shape.scale[0], shape.scale[1], shape.scale[2]);
    const url = shape.url;
    const ext = url.split('.').pop().toLowerCase();
    this.meshesPending++;
    const done = () => { this.meshesPending--; };
    const fail = () => { this.missingMeshes.push(url); done(); };
    if (ext === 'stl') {
      this.stlLoader.load(url, (geometry) => { geometry.computeVertexNormals(); holder.add(addMesh(geometry, material)); done(); },
                          undefined, fail);
    } else if (ext === 'dae') {
      this.colladaLoader.load(url, (collada) => {
        // URDF meshes are in the link frame: undo the loader's Z_UP turn (the unit scale stays).
        collada.scene.rotation.set(0, 0, 0);
        collada.scene.updateMatrix();
        collada.scene.traverse((c) => {
          if (c.isMesh) {
            if (shape.rgba) c.material = material;
            else if (entry) entry.materials.push(...[].concat(c.material));
            if (entry) { c.userData.link = entry.index; this.pickables.push(c); }
          }
        });
        holder.add(collada.scene);
        done();
      }, undefined, fail);
    } else if (ext === 'obj') {
      this.objLoader.load(url, (group) => {
        group.traverse((c) => {
          if (c.isMesh) {
            c.material = material;
            if (entry) { c.userData.link = entry.index; this.pickables.push(c); }
          }
        });
        holder.add(group);
        done();
      }, undefined, fail);
    } else {
      fail();
    }
    return holder;
  }

  linkIndex(name) { return this.links.findIndex((l) => l.name === name); }

  // Applies one frame from the igms process.
  update(frame) {
    const poses = frame.poses || [];
    const n = Math.min(poses.length, this.links.length);
    const m = new THREE.Matrix4(), q = new THREE.Quaternion(), p = new THREE.Vector3(), one = new THREE.Vector3(1, 1, 1);
    for (let i = 0; i < n; i++) {
      const x = poses[i];
      p.set(x[0], x[1], x[2]);
      q.set(x[4], x[5], x[6], x[3]);
      m.compose(p, q, one);
      this.links[i].group.matrix.copy(m);
      this.links[i].group.matrixWorldNeedsUpdate = true;
    }
    if (this.stickLines) {
      const a = this.stickLines.geometry.attributes.position;
      this.sticks.forEach(([from, to], k) => {
        const u = poses[from], v = poses[to];
        if (!u || !v) return;
        a.setXYZ(2 * k, u[0], u[1], u[2]);
        a.setXYZ(2 * k + 1, v[0], v[1], v[2]);
      });
      a.needsUpdate = true;
    }
    // Links in collision: the one nearest the obstacle glows.
    this.links.forEach((l, i) => {
      const hit = frame.in_collision && frame.closest_link === i;
      for (const material of l.materials) {
        if (material.emissive) material.emissive.copy(hit ? COLLISION_COLOUR : NO_GLOW);
      }
    });
    this.appendExecuted(frame, poses);
    this.updateInteraction(frame);
  }

  appendExecuted(frame, poses) {
    if (this.traced < 0 || !poses[this.traced]) return;
    if (this.lastSeq !== undefined && frame.seq < this.lastSeq) this.clearExecuted();  // the server was reset
    this.lastSeq = frame.seq;
    const x = poses[this.traced];
    const a = this.executed.geometry.attributes.position;
    if (this.executedCount > 0) {
      const k = this.executedCount - 1;
      const d = Math.hypot(a.getX(k) - x[0], a.getY(k) - x[1], a.getZ(k) - x[2]);
      if (d < 1e-4) return;
    }
    if (this.executedCount >= MAX_PATH_POINTS) return;
    a.setXYZ(this.executedCount, x[0], x[1], x[2]);
    // Upload the new point only, not the whole 20 000-point buffer.
    a.updateRange.offset = 3 * this.executedCount++;
    a.updateRange.count = 3;
    a.needsUpdate = true;
    this.executed.geometry.setDrawRange(0, this.executedCount);
  }

  updateInteraction(frame) {
    // The tip: the web device's own (smoothed) tip, else the client's input.
    const device = frame.device;
    const input = frame.input;
    let tip = null, radius = this.tipRadius || 0.01;
    if (device && device.active) tip = device.tip;
    else if (!device && input) { tip = input.tip; radius = input.radius || radius; }
    this.tip.visible = !!tip;
    if (tip) {
      this.tip.position.set(tip[0], tip[1], tip[2]);
      this.tip.scale.setScalar(radius);
      this.tip.material.color.set(frame.mode === 1 ? 0xff3d00 : 0xffa000);
    }
    // The force on the robot at its point of action.
    const f = frame.force || [0, 0, 0];
    const magnitude = Math.hypot(f[0], f[1], f[2]);
    const acting = frame.mode > 0 && magnitude > 1e-6;
    this.arrow.visible = acting;
    this.contact.visible = acting;
    if (acting) {
      const at = new THREE.Vector3(...frame.point);
      this.arrow.position.copy(at);
      this.arrow.setDirection(new THREE.Vector3(f[0] / magnitude, f[1] / magnitude, f[2] / magnitude));
      this.arrow.setLength(Math.max(magnitude * NEWTONS_TO_METRES, 0.02), 0.025, 0.015);
      this.contact.position.copy(at);
    }
    // The force the device renders, at the tip (pseudo-haptics).
    const rendered = device ? device.force : null;
    const rm = rendered ? Math.hypot(...rendered) : 0;
    this.deviceArrow.visible = !!tip && rm > 1e-3;
    if (this.deviceArrow.visible) {
      this.deviceArrow.position.set(tip[0], tip[1], tip[2]);
      this.deviceArrow.setDirection(new THREE.Vector3(rendered[0] / rm, rendered[1] / rm, rendered[2] / rm));
      this.deviceArrow.setLength(Math.max(rm * NEWTONS_TO_METRES, 0.02), 0.025, 0.015);
    }
    // The pull spring: from the attachment on the link to the tip.
    const pulling = frame.mode === 2 && input && input.attach_link;
    this.spring.visible = false;
    if (pulling && tip) {
      const link = this.linkIndex(input.attach_link);
      if (link >= 0) {
        const attach = new THREE.Vector3(...input.attach_point).applyMatrix4(this.links[link].group.matrix);
        const a = this.spring.geometry.attributes.position;
        a.setXYZ(0, attach.x, attach.y, attach.z);
        a.setXYZ(1, tip[0], tip[1], tip[2]);
        a.needsUpdate = true;
        this.spring.visible = true;
      }
    }
  }

  // The world position of a link's origin as drawn (for tests and the HUD).
  linkPosition(i) {
    const e = this.links[i].group.matrix.elements;
    return [e[12], e[13], e[14]];
  }

  // w x y z
  linkQuaternion(i) {
    const q = new THREE.Quaternion().setFromRotationMatrix(this.links[i].group.matrix);
    return [q.w, q.x, q.y, q.z];
  }

  // The nominal path's point at sim time t (null without a nominal path).
  nominalAt(t) {
    const path = this.hello && this.hello.nominal_path;
    const end = this.hello && this.hello.nominal_end;
    if (!path || path.length < 2 || !(end > 0)) return null;
    const s = Math.min(Math.max(t / end, 0), 1) * (path.length - 1);
    const k = Math.min(Math.floor(s), path.length - 2), u = s - k;
    return [0, 1, 2].map((j) => path[k][j] * (1 - u) + path[k + 1][j] * u);
  }
}
