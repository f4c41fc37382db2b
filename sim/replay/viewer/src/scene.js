// The 3D scene: ground, obstacles, modules (two hemispheres each, coloured by role, connectors and
// rubber rings), latches, the path trail and packets as brief links. The world is z-up as in sim/.
// Structures change: a module is drawn only while the recording says it is in the world (channel
// PRESENT), and a latch is drawn, over the shells, while data.links says it is closed.
import * as THREE from "three";
import { OrbitControls } from "three/addons/controls/OrbitControls.js";
import {
  LOST_COLOUR, MAX_PACKET_LINES, NO_ROLE_COLOUR, PACKET_COLOURS, PACKET_SHOWN_S, ROLE_COLOURS,
} from "./constants.js";
import { PRESENT, channel, lastAtOrBefore, linksAt, roleAt } from "./data.js";

const UP = new THREE.Vector3(0, 1, 0);
const LARGE = 40; // modules: above this, coarser shapes
const LATCH_COLOUR = 0x1b7f3b;
const HIDDEN = new THREE.Matrix4().makeScale(0, 0, 0);

export class Scene {
  constructor(rec, container) {
    this.rec = rec;
    const data = rec.data;
    this.roleColour = new Map(data.roles.map((name, i) => [name, ROLE_COLOURS[i % ROLE_COLOURS.length]]));
    this.renderer = new THREE.WebGLRenderer({ antialias: false });
    this.renderer.setPixelRatio(Math.min(window.devicePixelRatio || 1, 2));
    container.appendChild(this.renderer.domElement);
    this.scene = new THREE.Scene();
    this.scene.background = new THREE.Color(0xe9ecf0);
    this.camera = new THREE.PerspectiveCamera(45, 1, 0.01, 200);
    this.camera.up.set(0, 0, 1);
    this.controls = new OrbitControls(this.camera, this.renderer.domElement);
    this.controls.enableDamping = false;
    this.scene.add(new THREE.HemisphereLight(0xffffff, 0x667788, 1.6));
    const sun = new THREE.DirectionalLight(0xffffff, 1.4);
    sun.position.set(2, -3, 5);
    this.scene.add(sun);
    this.followCentre = new THREE.Vector3();
    this.follow = false;
    this.shownRoles = new Map();
    this.#ground();
    this.#obstacles();
    this.#modules();
    this.#trail();
    this.#packets();
    this.#latches();
    this.#frameCamera();
  }

  // the floor is the background colour under a grid: filling a floor plane cost software WebGL
  // more than all the modules
  #ground() {
    const size = 12;
    const grid = new THREE.GridHelper(size, size * 5, 0xb0b8c4, 0xd4d9e0);
    grid.rotation.x = Math.PI / 2;
    this.scene.add(grid);
  }

  #obstacles() {
    const h = this.rec.data.obstacle_height;
    const material = new THREE.MeshLambertMaterial({ color: 0x8d6e63, transparent: true, opacity: 0.85 });
    for (const box of this.rec.data.obstacles) {
      const mesh = new THREE.Mesh(new THREE.BoxGeometry(box.w, box.l, h), material);
      mesh.position.set(box.x, box.y, h / 2);
      this.scene.add(mesh);
    }
  }

  // every module's parts as a few instanced meshes: a handful of draw calls for any structure
  #modules() {
    const data = this.rec.data;
    const r = data.module_radius;
    const m = data.modules.length;
    // few triangles: software WebGL (no GPU) must still draw 100 modules at 30 frames a second,
    // and vertices are what it spends its time on; large structures get coarser shells
    const [around, rings, disc] = m <= LARGE ? [16, 5, 8] : [10, 3, 6];
    const shell = new THREE.SphereGeometry(r, around, rings, 0, Math.PI * 2, 0, Math.PI / 2);
    const connector = new THREE.CircleGeometry(r * 0.24, disc).rotateX(-Math.PI / 2); // a disc facing +y
    const ring = new THREE.TorusGeometry(data.ring.radius - data.ring.width / 4, data.ring.width / 2, 4, 20);
    this.shells = new THREE.InstancedMesh(shell, new THREE.MeshLambertMaterial({ color: 0xffffff }), 2 * m);
    // connectors alternate dark and light (so a turning joint shows); one draw call for all of them
    this.connectors = new THREE.InstancedMesh(connector, new THREE.MeshLambertMaterial({ color: 0xffffff }), 8 * m);
    const wheels = data.modules.filter((module) => module.wheel !== 0).length;
    this.rings = new THREE.InstancedMesh(ring, new THREE.MeshLambertMaterial({ color: 0x222222 }), Math.max(1, wheels));
    this.rings.count = wheels;
    const white = new THREE.Color(0xffffff);
    for (const mesh of [this.shells, this.connectors, this.rings]) {
      mesh.instanceMatrix.setUsage(THREE.DynamicDrawUsage);
      mesh.frustumCulled = false;
      this.scene.add(mesh);
    }
    for (let k = 0; k < 2 * m; k++) this.shells.setColorAt(k, white);
    let plug = 0;
    const dark = new THREE.Color(0x333333);
    const light = new THREE.Color(0xf0f0f0);
    let tyre = 0;
    const one = new THREE.Vector3(1, 1, 1);
    this.modules = data.modules.map((module, i) => {
      const pole = new THREE.Vector3(...module.pole);
      const halves = [1, -1].map((side, h) => {
        // parts of the hemisphere in its own frame (the lattice frame at the start, centre at 0)
        const parts = [{ mesh: this.shells, index: 2 * i + h,
          local: new THREE.Matrix4().makeRotationFromQuaternion(
            new THREE.Quaternion().setFromUnitVectors(UP, pole.clone().multiplyScalar(side))) }];
        for (let v = side > 0 ? 0 : 4; v < (side > 0 ? 4 : 8); v++) {
          const d = new THREE.Vector3(...module.connectors[v]);
          const q = new THREE.Quaternion().setFromUnitVectors(UP, d);
          const local = new THREE.Matrix4().compose(d.clone().multiplyScalar(r * 1.003), q, one);
          this.connectors.setColorAt(plug, v % 2 === 0 ? dark : light);
          parts.push({ mesh: this.connectors, index: plug++, local });
        }
        if (module.wheel === side) {
          const q = new THREE.Quaternion().setFromUnitVectors(new THREE.Vector3(0, 0, 1), pole);
          const local = new THREE.Matrix4().compose(pole.clone().multiplyScalar(side * data.ring.offset), q, one);
          parts.push({ mesh: this.rings, index: tyre++, local });
        }
        return { parts, quaternion: new THREE.Quaternion() };
      });
      return { id: module.id, module, halves, centre: new THREE.Vector3(), colour: new THREE.Color(NO_ROLE_COLOUR),
        present: true };
    });
    this.pickable = [this.shells];
  }

  #place(m) {
    if (!m.present) {
      for (const half of m.halves) for (const part of half.parts) part.mesh.setMatrixAt(part.index, HIDDEN);
      return;
    }
    const holder = new THREE.Matrix4();
    const world = new THREE.Matrix4();
    const one = new THREE.Vector3(1, 1, 1);
    for (const half of m.halves) {
      holder.compose(m.centre, half.quaternion, one);
      for (const part of half.parts) part.mesh.setMatrixAt(part.index, world.multiplyMatrices(holder, part.local));
    }
  }

  #trail() {
    const rec = this.rec;
    const positions = new Float32Array(Math.max(rec.n, 1) * 3);
    for (let s = 0; s < rec.n; s++) {
      let x = 0;
      let y = 0;
      let count = 0;
      for (let i = 0; i < rec.m; i++) {
        if (!channel(rec, i, PRESENT, s)) continue;
        x += channel(rec, i, 0, s);
        y += channel(rec, i, 1, s);
        count++;
      }
      count = Math.max(1, count);
      positions.set([x / count / 1000, y / count / 1000, 0.002], s * 3);
    }
    const geometry = new THREE.BufferGeometry();
    geometry.setAttribute("position", new THREE.BufferAttribute(positions, 3));
    this.trail = new THREE.Line(geometry, new THREE.LineBasicMaterial({ color: 0x2a6f97 }));
    this.trailPoints = positions;
    this.scene.add(this.trail);
  }

  #packets() {
    const make = (material) => {
      const geometry = new THREE.BufferGeometry();
      geometry.setAttribute("position", new THREE.BufferAttribute(new Float32Array(MAX_PACKET_LINES * 6), 3));
      geometry.setAttribute("color", new THREE.BufferAttribute(new Float32Array(MAX_PACKET_LINES * 6), 3));
      const lines = new THREE.LineSegments(geometry, material);
      lines.frustumCulled = false;
      this.scene.add(lines);
      return lines;
    };
    this.packetLines = make(new THREE.LineBasicMaterial({ vertexColors: true }));
    this.lostLines = make(new THREE.LineDashedMaterial({ color: LOST_COLOUR, dashSize: 0.012, gapSize: 0.01 }));
  }

  // latches: a line between the centres of the two modules, drawn over the shells
  #latches() {
    const count = Math.max(1, this.rec.data.links?.length ?? 0);
    const geometry = new THREE.BufferGeometry();
    geometry.setAttribute("position", new THREE.BufferAttribute(new Float32Array(count * 6), 3));
    this.latchLines = new THREE.LineSegments(geometry, new THREE.LineBasicMaterial({
      color: LATCH_COLOUR, depthTest: false, transparent: true, opacity: 0.9 }));
    this.latchLines.renderOrder = 10;
    this.latchLines.frustumCulled = false;
    this.scene.add(this.latchLines);
    this.shownLinks = [];
  }

  #updateLatches(t) {
    const shown = linksAt(this.rec.data.links ?? [], t);
    const position = this.latchLines.geometry.attributes.position.array;
    let k = 0;
    this.shownLinks = [];
    for (const [a, ap, b, bp] of shown) {
      const ma = this.modules[this.rec.index.get(a)];
      const mb = this.modules[this.rec.index.get(b)];
      if (!ma || !mb || !ma.present || !mb.present || 6 * (k + 1) > position.length) continue;
      position.set([ma.centre.x, ma.centre.y, ma.centre.z, mb.centre.x, mb.centre.y, mb.centre.z], k * 6);
      this.shownLinks.push([a, ap, b, bp]);
      k++;
    }
    this.latchLines.geometry.setDrawRange(0, k * 2);
    this.latchLines.geometry.attributes.position.needsUpdate = true;
  }

  // the centre of the modules in the world now
  #present() {
    const here = this.modules.filter((m) => m.present);
    return here.length ? here : this.modules;
  }

  #frameCamera() {
    this.update(0);
    const centre = new THREE.Vector3();
    const here = this.#present();
    for (const m of here) centre.add(m.centre);
    centre.divideScalar(here.length);
    const span = Math.max(0.55, Math.sqrt(this.rec.m) * 0.14);
    this.controls.target.copy(centre);
    this.camera.position.set(centre.x - span * 1.6, centre.y - span * 2.2, centre.z + span * 1.8);
    this.controls.update();
    this.followCentre.copy(centre);
  }

  resize(width, height) {
    this.renderer.setSize(width, height, false);
    this.camera.aspect = width / Math.max(1, height);
    this.camera.updateProjectionMatrix();
  }

  // place everything at time t (interpolating between samples)
  update(t) {
    const rec = this.rec;
    const s = Math.max(0, lastAtOrBefore(rec.times, t));
    const s2 = Math.min(rec.n - 1, s + 1);
    const span = rec.times[s2] - rec.times[s];
    const f = span > 0 ? Math.min(1, Math.max(0, (t - rec.times[s]) / span)) : 0;
    const qa = new THREE.Quaternion();
    const qb = new THREE.Quaternion();
    for (let i = 0; i < this.modules.length; i++) {
      const m = this.modules[i];
      m.present = channel(rec, i, PRESENT, s) !== 0;
      // a module that appears or goes at the next sample does not glide: it stays at this pose
      const g = channel(rec, i, PRESENT, s2) !== 0 && m.present ? f : 0;
      const at = (c) => channel(rec, i, c, s) * (1 - g) + channel(rec, i, c, s2) * g;
      m.centre.set(at(0) / 1000, at(1) / 1000, at(2) / 1000);
      m.halves.forEach((half, h) => {
        const c0 = 3 + 4 * h;
        qa.set(channel(rec, i, c0, s), channel(rec, i, c0 + 1, s), channel(rec, i, c0 + 2, s),
          channel(rec, i, c0 + 3, s)).normalize();
        qb.set(channel(rec, i, c0, s2), channel(rec, i, c0 + 1, s2), channel(rec, i, c0 + 2, s2),
          channel(rec, i, c0 + 3, s2)).normalize();
        half.quaternion.slerpQuaternions(qa, qb, g);
      });
      this.#place(m);
      const role = roleAt(m.module, t);
      if (this.shownRoles.get(m.id) !== role || !this.shownRoles.has(m.id)) {
        this.shownRoles.set(m.id, role);
        m.colour.set(role === null ? NO_ROLE_COLOUR : this.roleColour.get(role) ?? NO_ROLE_COLOUR);
        this.shells.setColorAt(2 * i, m.colour);
        this.shells.setColorAt(2 * i + 1, m.colour.clone().multiplyScalar(0.82));
        this.shells.instanceColor.needsUpdate = true;
      }
    }
    for (const mesh of [this.shells, this.connectors, this.rings]) {
      mesh.instanceMatrix.needsUpdate = true;
    }
    this.trail.geometry.setDrawRange(0, s + 1);
    this.#updateLatches(t);
    this.#updatePackets(t);
    if (this.follow) this.#followRobot();
  }

  #updatePackets(t) {
    const p = this.rec.packets;
    const last = lastAtOrBefore(p.t, t);
    let ok = 0;
    let lost = 0;
    const okPos = this.packetLines.geometry.attributes.position.array;
    const okCol = this.packetLines.geometry.attributes.color.array;
    const lostPos = this.lostLines.geometry.attributes.position.array;
    const colour = new THREE.Color();
    for (let k = last; k >= 0 && p.t[k] > t - PACKET_SHOWN_S; k--) {
      const a = this.modules[this.rec.index.get(p.from[k])]?.centre;
      const b = this.modules[this.rec.index.get(p.to[k])]?.centre;
      if (!a || !b) continue;
      if (p.dropped[k]) {
        if (lost >= MAX_PACKET_LINES) continue;
        // a lost packet stops half-way
        lostPos.set([a.x, a.y, a.z + 0.03, (a.x + b.x) / 2, (a.y + b.y) / 2, (a.z + b.z) / 2 + 0.03], lost * 6);
        lost++;
      } else {
        if (ok >= MAX_PACKET_LINES) continue;
        okPos.set([a.x, a.y, a.z + 0.03, b.x, b.y, b.z + 0.03], ok * 6);
        colour.setHex(PACKET_COLOURS[p.kind[k]] ?? 0xffffff);
        okCol.set([colour.r, colour.g, colour.b, colour.r, colour.g, colour.b], ok * 6);
        ok++;
      }
    }
    this.packetLines.geometry.setDrawRange(0, ok * 2);
    this.packetLines.geometry.attributes.position.needsUpdate = true;
    this.packetLines.geometry.attributes.color.needsUpdate = true;
    this.lostLines.geometry.setDrawRange(0, lost * 2);
    this.lostLines.geometry.attributes.position.needsUpdate = true;
    if (lost) this.lostLines.computeLineDistances();
    this.shownPackets = { ok, lost };
  }

  #followRobot() {
    const centre = new THREE.Vector3();
    const here = this.#present();
    for (const m of here) centre.add(m.centre);
    centre.divideScalar(here.length);
    const delta = centre.clone().sub(this.controls.target);
    this.controls.target.add(delta);
    this.camera.position.add(delta);
    this.controls.update();
  }

  render() {
    this.renderer.render(this.scene, this.camera);
  }

  // module id under the canvas point (client coordinates), or null
  pickAt(clientX, clientY) {
    const rect = this.renderer.domElement.getBoundingClientRect();
    const ndc = new THREE.Vector2(((clientX - rect.left) / rect.width) * 2 - 1,
      -((clientY - rect.top) / rect.height) * 2 + 1);
    const ray = new THREE.Raycaster();
    ray.setFromCamera(ndc, this.camera);
    this.shells.computeBoundingSphere(); // instances move: the cached sphere would be stale
    const hit = ray.intersectObjects(this.pickable, false)[0];
    return hit && hit.instanceId !== undefined ? this.modules[hit.instanceId >> 1].id : null;
  }

  // where module `id` is on the screen (client coordinates), for tests and the panel
  screenPoint(id) {
    const m = this.modules[this.rec.index.get(id)];
    const v = m.centre.clone().project(this.camera);
    const rect = this.renderer.domElement.getBoundingClientRect();
    return { x: rect.left + ((v.x + 1) / 2) * rect.width, y: rect.top + ((1 - v.y) / 2) * rect.height };
  }

  colourOf(id) {
    return "#" + this.modules[this.rec.index.get(id)].colour.getHexString();
  }
}
