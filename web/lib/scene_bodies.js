// What moves in a live session as its scene frames (lib/scene_frame.js) give it: people's body
// capsules, robots' links where the joints put them, movable objects where they are now, doors' closed
// shares. Instanced meshes draw every part (boxes, cylinders, spheres; a capsule is an open cylinder
// and two half spheres, coarser: people are many and small), so a frame costs no new geometry, only
// matrices and colours. Between two frames each part goes from where the older frame had it to where
// the newer one has it (pose(progress)).
import * as THREE from 'three';
import { SHAPE, partKind } from './scene_frame.js';

/** Frames further apart in simulated time are not interpolated (a seek or a reset lies between them), s. */
const MAX_INTERPOLATED_S = 1.0;
/** Arrivals further apart than this mean the motion had stopped (paused, single steps): jump, ms. */
const MAX_MOTION_MS = 500;
/** Instances the meshes hold at first; they double when a frame needs more. */
const INITIAL_CAPACITY = 128;

/**
 * How long the way from one frame to the next lasts on screen: the time between the arrivals of the
 * last frames (smoothed), so that the motion is continuous at whatever rate the frames come.
 */
export class Motion {
  #last = -Infinity;
  #start = 0;
  #duration = 0;

  /** A new target arrived at `now` (ms). */
  arrive(now) {
    const gap = now - this.#last;
    this.#last = now;
    this.#start = now;
    this.#duration = gap > MAX_MOTION_MS ? 0 : this.#duration ? (this.#duration + gap) / 2 : gap;
  }

  /** 0 at the arrival, 1 once the last gap has passed (and when there is no motion). */
  progress(now) {
    return this.#duration > 0 ? Math.min(Math.max((now - this.#start) / this.#duration, 0), 1) : 1;
  }
}

const scratch = {
  a: new THREE.Vector3(), b: new THREE.Vector3(), centre: new THREE.Vector3(), scale: new THREE.Vector3(),
  q: new THREE.Quaternion(), q0: new THREE.Quaternion(),
  turnOver: new THREE.Quaternion().setFromAxisAngle(new THREE.Vector3(1, 0, 0), Math.PI),
  matrix: new THREE.Matrix4(), colour: new THREE.Color(), up: new THREE.Vector3(0, 0, 1),
};

export class SceneBodies {
  /** The parts are drawn under `parent` (a three.js Object3D). */
  constructor(parent) {
    this.group = new THREE.Group();
    this.group.name = 'scene frame';
    parent.add(this.group);
    this.material = new THREE.MeshLambertMaterial({ color: 0xffffff });  // each instance's colour multiplies it
    // Cylinders have radius 1 and their axis along z, as the frame's.
    this.geometries = {
      box: new THREE.BoxGeometry(1, 1, 1),
      cylinder: new THREE.CylinderGeometry(1, 1, 1, 16).rotateX(Math.PI / 2),
      sphere: new THREE.SphereGeometry(1, 16, 10),
      shaft: new THREE.CylinderGeometry(1, 1, 1, 10, 1, true).rotateX(Math.PI / 2),  // open: the caps close it
      cap: new THREE.SphereGeometry(1, 10, 3, 0, 2 * Math.PI, 0, Math.PI / 2).rotateX(Math.PI / 2),  // the half towards +z
    };
    this.meshes = {};
    for (const kind of Object.keys(this.geometries)) this.#grow(kind, INITIAL_CAPACITY);
    this.frame = null;
    this.previous = null;
    // Per record of the frame: the record of the previous frame it moves from (-1: none) and its slots
    // in the meshes (a capsule's cylinder, then its first sphere).
    this.from = new Int32Array(0);
    this.slots = new Int32Array(0);
    this.counts = { person: 0, robot: 0, object: 0, door: 0 };
    this.received = 0;
  }

  /** Replaces the mesh of `kind` with one that holds `capacity` instances (rare: the meshes only grow). */
  #grow(kind, capacity) {
    const old = this.meshes[kind];
    if (old) {
      this.group.remove(old);
      old.dispose();
    }
    const mesh = new THREE.InstancedMesh(this.geometries[kind], this.material, capacity);
    mesh.instanceMatrix.setUsage(THREE.DynamicDrawUsage);
    mesh.setColorAt(0, scratch.colour.setRGB(1, 1, 1));  // makes its colour buffer
    mesh.frustumCulled = false;  // its bounds would be those of the first instance
    mesh.count = 0;
    mesh.name = `scene ${kind}s`;
    this.group.add(mesh);
    this.meshes[kind] = mesh;
  }

  /** The next frame: the parts move from the frame before (when it is close in time) to it. */
  setFrame(frame) {
    const previous = this.frame;
    const dt = previous ? frame.time - previous.time : 0;
    this.previous = dt > 0 && dt <= MAX_INTERPOLATED_S ? previous : null;
    this.frame = frame;
    this.received += 1;
    if (this.from.length < frame.count) {
      this.from = new Int32Array(frame.count * 2);
      this.slots = new Int32Array(frame.count * 4);
    }
    this.#match();
    const used = { box: 0, cylinder: 0, sphere: 0, shaft: 0, cap: 0 };
    const counts = { person: 0, robot: 0, object: 0, door: 0 };
    for (let i = 0; i < frame.count; i++) {
      const shape = frame.shape(i);
      const kind = partKind(frame.id(i), shape);
      if (kind in counts) counts[kind] += 1;
      if (shape === SHAPE.capsule) {
        this.slots[2 * i] = used.shaft++;
        this.slots[2 * i + 1] = used.cap;
        used.cap += 2;
      } else {
        const mesh = shape === SHAPE.box ? 'box' : shape === SHAPE.sphere ? 'sphere' : 'cylinder';
        this.slots[2 * i] = used[mesh]++;
        this.slots[2 * i + 1] = -1;
      }
    }
    this.counts = counts;
    for (const [kind, count] of Object.entries(used)) {
      if (count > this.meshes[kind].instanceMatrix.count) this.#grow(kind, Math.max(count, 2 * this.meshes[kind].instanceMatrix.count));
      this.meshes[kind].count = count;
    }
    this.#colour();
  }

  /**
   * Which record of the previous frame each record moves from: the same id, in the same order (a
   * person's 13 capsules share one), skipping records that came or went (a door opened all the way).
   */
  #match() {
    const { frame, previous, from } = this;
    let next = 0;
    for (let i = 0; i < frame.count; i++) {
      from[i] = -1;
      if (!previous) continue;
      const id = frame.id(i);
      let j = next;
      while (j < previous.count && previous.id(j) !== id) j++;
      if (j === previous.count) continue;  // a part that was not there
      if (previous.shape(j) === frame.shape(i)) from[i] = j;
      next = j + 1;
    }
  }

  #colour() {
    const { frame, slots, meshes } = this;
    for (let i = 0; i < frame.count; i++) {
      const colour = scratch.colour.setRGB(frame.colour(i, 0), frame.colour(i, 1), frame.colour(i, 2));  // linear, as three.js works
      const shape = frame.shape(i);
      if (shape === SHAPE.capsule) {
        meshes.shaft.setColorAt(slots[2 * i], colour);
        meshes.cap.setColorAt(slots[2 * i + 1], colour);
        meshes.cap.setColorAt(slots[2 * i + 1] + 1, colour);
      } else {
        meshes[shape === SHAPE.box ? 'box' : shape === SHAPE.sphere ? 'sphere' : 'cylinder'].setColorAt(slots[2 * i], colour);
      }
    }
    for (const mesh of Object.values(meshes)) mesh.instanceColor.needsUpdate = true;
  }

  /** Float k of record i, `progress` of the way from its record in the previous frame. */
  #float(i, k, progress) {
    const to = this.frame.float(i, k);
    const j = this.from[i];
    if (j < 0 || progress >= 1) return to;
    const from = this.previous.float(j, k);
    return from + (to - from) * progress;
  }

  /** Puts every part `progress` (0–1) of the way from the previous frame to the last one. */
  pose(progress) {
    const { frame, slots, meshes } = this;
    if (!frame) return;
    const { a, b, centre, scale, q, q0, turnOver, matrix, up } = scratch;
    for (let i = 0; i < frame.count; i++) {
      a.set(this.#float(i, 0, progress), this.#float(i, 1, progress), this.#float(i, 2, progress));
      b.set(this.#float(i, 3, progress), this.#float(i, 4, progress), this.#float(i, 5, progress));
      const shape = frame.shape(i);
      if (shape === SHAPE.capsule) {
        const radius = this.#float(i, 6, progress);
        const length = b.distanceTo(a);
        centre.addVectors(a, b).multiplyScalar(0.5);
        if (length > 1e-9) q.setFromUnitVectors(up, b.sub(a).divideScalar(length));
        else q.identity();
        meshes.shaft.setMatrixAt(slots[2 * i], matrix.compose(centre, q, scale.set(radius, radius, length)));
        scale.setScalar(radius);
        b.copy(centre).multiplyScalar(2).sub(a);  // the other end again
        meshes.cap.setMatrixAt(slots[2 * i + 1] + 1, matrix.compose(b, q, scale));
        meshes.cap.setMatrixAt(slots[2 * i + 1], matrix.compose(a, q.multiply(turnOver), scale));
        continue;
      }
      q.set(frame.float(i, 6), frame.float(i, 7), frame.float(i, 8), frame.float(i, 9));
      const j = this.from[i];
      if (j >= 0 && progress < 1) {
        q0.set(this.previous.float(j, 6), this.previous.float(j, 7), this.previous.float(j, 8), this.previous.float(j, 9));
        q.slerpQuaternions(q0, q, progress);
      }
      if (shape === SHAPE.box) meshes.box.setMatrixAt(slots[2 * i], matrix.compose(a, q, b));
      else if (shape === SHAPE.sphere) meshes.sphere.setMatrixAt(slots[2 * i], matrix.compose(a, q, b.multiplyScalar(0.5)));
      else meshes.cylinder.setMatrixAt(slots[2 * i], matrix.compose(a, q, scale.set(b.x / 2, b.y / 2, b.z)));
    }
    for (const mesh of Object.values(meshes)) mesh.instanceMatrix.needsUpdate = true;
  }

  /**
   * For tests and debugging: the frames received, the last one's tick, its parts by kind and the
   * centre of each instance id's parts ({id: [x, y, z]}).
   */
  summary() {
    const { frame } = this;
    if (!frame) return null;
    const sums = {};
    for (let i = 0; i < frame.count; i++) {
      const capsule = frame.shape(i) === SHAPE.capsule;
      const sum = (sums[frame.id(i)] ??= [0, 0, 0, 0]);
      for (let k = 0; k < 3; k++) sum[k] += capsule ? (frame.float(i, k) + frame.float(i, k + 3)) / 2 : frame.float(i, k);
      sum[3] += 1;
    }
    const centres = Object.fromEntries(Object.entries(sums).map(([id, [x, y, z, n]]) => [id, [x / n, y / n, z / n]]));
    return { received: this.received, tick: frame.tick, time: frame.time, parts: { ...this.counts }, centres };
  }

  dispose() {
    this.group.removeFromParent();
    for (const mesh of Object.values(this.meshes)) mesh.dispose();
    for (const geometry of Object.values(this.geometries)) geometry.dispose();
    this.material.dispose();
  }
}
