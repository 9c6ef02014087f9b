// A scenario in 3D with three.js, from GET /api/v1/scenarios/{id}/world: floor, walls, furniture,
// doors, movable objects (where they start), locations and social spaces, with live agents, paths, a
// laser scan and proxemic rings on top. Given a session's scene frames (setSceneFrame), it draws what
// moves as they have it (lib/scene_bodies.js: people's bodies, robots' links, objects, doors) instead.
// Map frame as everywhere in hrisim: x right, y up (north), z up from the floor, metres and radians.
// It renders on demand (something changed, or the view is being moved), so an idle page costs
// nothing; while animating (a session playing) at every display frame, moving what moves between the
// poses it was last given.
import * as THREE from 'three';
import { OrbitControls } from 'three/addons/controls/OrbitControls.js';
import { mergeGeometries } from 'three/addons/utils/BufferGeometryUtils.js';
import { palette } from './map2d.js';
import { SceneBodies, Motion } from './scene_bodies.js';

/** Hall's proxemic distances (The Hidden Dimension, 1966), outer limits in m. */
export const PROXEMIC_DISTANCES = Object.freeze({ intimate: 0.45, personal: 1.2, social: 3.6 });

/** Walls of a map from an image are drawn this high when the world gives no top, m. */
const DEFAULT_WALL_HEIGHT = 2.0;
/** Doors are slabs this high, m. */
const DOOR_HEIGHT = 2.0;
/** A person: body cylinder height and head radius, m (about the adult body of docs/rendering.md). */
const BODY_HEIGHT = 1.4;
const HEAD_RADIUS = 0.12;
/** A person's label, above the head of an adult's body (1.75 m), m. */
const HUMAN_LABEL_HEIGHT = 2.1;
/** A robot without a model drawn as a cylinder this high, m, with a mast on top. */
const ROBOT_BASE_HEIGHT = 0.45;
const ROBOT_MAST_HEIGHT = 0.6;
/** Lines on the floor sit slightly above it so they never fight with it for depth. */
const FLOOR_LIFT = 0.02;
/** The perspective view: vertical field of view (degrees) and the angle it looks down at first (rad). */
const PERSPECTIVE_FOV = 45;
const PERSPECTIVE_ELEVATION = 0.95;
/** Where the laser points are drawn when the reading has no height, m. */
const DEFAULT_LASER_HEIGHT = 0.2;

const colours = {
  floor: 0xecebe6,
  grid: 0xd6d3ca,
  background: 0xf6f7f9,
  wall: new THREE.Color(palette.wall),
  furniture: new THREE.Color(palette.obstacle),
  door: new THREE.Color(palette.door),
  object: new THREE.Color(palette.object),
  location: new THREE.Color(palette.location),
  space: new THREE.Color(palette.space),
  human: new THREE.Color(palette.human),
  humanIdle: new THREE.Color('#7ea6e6'),
  robot: new THREE.Color(palette.robot),
  robotDark: new THREE.Color('#9c530c'),
  laser: new THREE.Color('#d62828'),
  proxemic: [new THREE.Color('#c0392b'), new THREE.Color('#d68910'), new THREE.Color('#2f8a4f')],
};

/** A flat arrow pointing along +x, from x = 0 to x = 1, lying in the xy plane. */
function arrowGeometry() {
  const shape = new THREE.Shape();
  shape.moveTo(0, -0.08);
  shape.lineTo(0.6, -0.08);
  shape.lineTo(0.6, -0.25);
  shape.lineTo(1, 0);
  shape.lineTo(0.6, 0.25);
  shape.lineTo(0.6, 0.08);
  shape.lineTo(0, 0.08);
  shape.closePath();
  return new THREE.ShapeGeometry(shape);
}

/** A text label that always faces the camera, `height` m tall. */
function labelSprite(text, colour = '#1d2330', height = 0.35) {
  const canvas = document.createElement('canvas');
  const context = canvas.getContext('2d');
  const font = '600 40px system-ui, sans-serif';
  context.font = font;
  const width = Math.ceil(context.measureText(text).width) + 20;
  canvas.width = width;
  canvas.height = 56;
  context.font = font;
  context.fillStyle = 'rgba(255, 255, 255, 0.8)';
  context.fillRect(0, 0, width, 56);
  context.fillStyle = colour;
  context.textBaseline = 'middle';
  context.fillText(text, 10, 29);
  const texture = new THREE.CanvasTexture(canvas);
  texture.colorSpace = THREE.SRGBColorSpace;
  const sprite = new THREE.Sprite(new THREE.SpriteMaterial({ map: texture, depthTest: false, transparent: true }));
  sprite.scale.set(height * width / 56, height, 1);
  sprite.renderOrder = 10;
  return sprite;
}

function polyline(points, z, material) {
  const geometry = new THREE.BufferGeometry().setFromPoints(points.map(([x, y]) => new THREE.Vector3(x, y, z)));
  return new THREE.Line(geometry, material);
}

let software = null;

/**
 * Whether WebGL runs in software (SwiftShader, llvmpipe: no GPU), asked once of a context made to
 * ask. There 4× multisampling about halves the frame rate, so the view goes without it.
 */
function softwareGl() {
  if (software === null) {
    const gl = document.createElement('canvas').getContext('webgl2');
    const info = gl?.getExtension('WEBGL_debug_renderer_info');
    const name = gl ? gl.getParameter(info ? info.UNMASKED_RENDERER_WEBGL : gl.RENDERER) : '';
    gl?.getExtension('WEBGL_lose_context')?.loseContext();
    software = /swiftshader|llvmpipe|softpipe|software/i.test(name);
  }
  return software;
}

/** A box from `from` to `to` on the floor, `thickness` wide and `height` high, where it stands. */
function slabGeometry(from, to, thickness, height) {
  const dx = to[0] - from[0], dy = to[1] - from[1];
  return new THREE.BoxGeometry(Math.hypot(dx, dy), thickness, height)
    .rotateZ(Math.atan2(dy, dx))
    .translate((from[0] + to[0]) / 2, (from[1] + to[1]) / 2, height / 2);
}

/**
 * One mesh of `geometries` (each already where it goes): the static map is a few draw calls, not one a
 * piece (each costs about 0.3 ms a frame in software GL). null when there are none.
 */
function mergedMesh(geometries, material) {
  if (!geometries.length) return null;
  const mesh = new THREE.Mesh(mergeGeometries(geometries), material);
  for (const geometry of geometries) geometry.dispose();
  return mesh;
}

/** Frees the GPU resources of everything under `root`. */
function disposeTree(root) {
  root.traverse((object) => {
    if (object.geometry && !object.geometry.userData.shared) object.geometry.dispose();
    const materials = Array.isArray(object.material) ? object.material : object.material ? [object.material] : [];
    for (const material of materials) {
      if (material.userData.shared) continue;
      if (material.map) material.map.dispose();
      material.dispose();
    }
  });
}

export class SceneView {
  /**
   * A view of `world` (GET /api/v1/scenarios/{id}/world) filling the width of `container`, `height`
   * pixels high. The container gets `data-frames`, the count of frames rendered so far.
   */
  constructor(container, world, { height = 480 } = {}) {
    this.container = container;
    this.world = world;
    this.height = height;
    this.frames = 0;
    this.frameRequest = 0;
    this.disposed = false;

    const [x0, y0] = world.bounds.min;
    const [x1, y1] = world.bounds.max;
    this.centre = new THREE.Vector3((x0 + x1) / 2, (y0 + y1) / 2, 0);
    this.span = { x: x1 - x0, y: y1 - y0 };
    // Labels grow with the map so that they stay readable when the whole map is in view.
    this.labelHeight = Math.min(Math.max(Math.max(this.span.x, this.span.y) / 40, 0.3), 1.0);

    // No preserveDrawingBuffer: keeping each frame costs a copy a frame, a third of the frame rate in
    // software GL. Tests read what the screen shows instead.
    this.renderer = new THREE.WebGLRenderer({ antialias: !softwareGl(), preserveDrawingBuffer: false });
    this.renderer.setPixelRatio(Math.min(window.devicePixelRatio || 1, 2));
    this.renderer.setClearColor(colours.background);
    this.renderer.domElement.classList.add('scene-canvas');
    container.append(this.renderer.domElement);

    this.scene = new THREE.Scene();
    this.scene.add(new THREE.HemisphereLight(0xffffff, 0x8d8a80, 2.2));
    const sun = new THREE.DirectionalLight(0xffffff, 1.4);
    sun.position.set(this.centre.x - 0.4 * this.span.x, this.centre.y - 0.6 * this.span.y, 25);
    sun.target.position.copy(this.centre);
    this.scene.add(sun, sun.target);

    // Geometries and materials every agent shares; freed once in dispose().
    this.shared = {
      cylinder: new THREE.CylinderGeometry(1, 1, 1, 24).rotateX(Math.PI / 2).translate(0, 0, 0.5),
      sphere: new THREE.SphereGeometry(1, 16, 12),
      box: new THREE.BoxGeometry(1, 1, 1).translate(0, 0, 0.5),
      arrow: arrowGeometry(),
      human: new THREE.MeshLambertMaterial({ color: colours.human }),
      humanIdle: new THREE.MeshLambertMaterial({ color: colours.humanIdle }),
      head: new THREE.MeshLambertMaterial({ color: 0xe8c4a0 }),
      robot: new THREE.MeshLambertMaterial({ color: colours.robot }),
      robotDark: new THREE.MeshLambertMaterial({ color: colours.robotDark }),
      humanArrow: new THREE.MeshBasicMaterial({ color: colours.human, side: THREE.DoubleSide }),
      humanIdleArrow: new THREE.MeshBasicMaterial({ color: colours.humanIdle, side: THREE.DoubleSide }),
      robotArrow: new THREE.MeshBasicMaterial({ color: colours.robotDark, side: THREE.DoubleSide }),
      laser: new THREE.PointsMaterial({ color: colours.laser, size: 3, sizeAttenuation: false }),
    };
    for (const item of Object.values(this.shared)) item.userData.shared = true;
    // Paths' materials by colour and dash, kept: a material freed with the last user of its shader frees
    // the shader, and compiling it again for the next one is slow (tens of ms in software GL).
    this.lineMaterials = new Map();

    this.buildMap();
    this.layers = { paths: new THREE.Group(), agents: new THREE.Group(), laser: new THREE.Group(), rings: new THREE.Group() };
    for (const layer of Object.values(this.layers)) this.scene.add(layer);
    this.agents = new Map();
    this.agentMotion = new Motion();
    this.paths = new Map();
    this.lasers = new Map();
    this.ringRadii = null;
    this.ringsFollow = null;
    this.bodies = new SceneBodies(this.scene);
    this.bodyMotion = new Motion();
    this.animating = false;

    this.onChange = () => this.invalidate();
    this.cameraListeners = [];
    this.onCameraEnd = () => { for (const listener of this.cameraListeners) listener(this.cameraPose()); };
    this.setView('top');
    this.resizeObserver = new ResizeObserver(() => this.resize());
    this.resizeObserver.observe(container);
    this.resize();
  }

  buildMap() {
    const world = this.world;
    const base = new THREE.Group();
    const floor = new THREE.Mesh(new THREE.PlaneGeometry(this.span.x, this.span.y), new THREE.MeshLambertMaterial({ color: colours.floor }));
    floor.position.copy(this.centre);
    base.add(floor);

    // A 1 m grid, to read distances by eye.
    const [x0, y0] = world.bounds.min;
    const [x1, y1] = world.bounds.max;
    const grid = [];
    for (let x = Math.ceil(x0); x <= x1; x++) grid.push(new THREE.Vector3(x, y0, 0.002), new THREE.Vector3(x, y1, 0.002));
    for (let y = Math.ceil(y0); y <= y1; y++) grid.push(new THREE.Vector3(x0, y, 0.002), new THREE.Vector3(x1, y, 0.002));
    base.add(new THREE.LineSegments(new THREE.BufferGeometry().setFromPoints(grid), new THREE.LineBasicMaterial({ color: colours.grid })));

    const walls = [], furniture = [];
    for (const obstacle of world.obstacles) {
      const shape = new THREE.Shape(obstacle.polygon.map(([x, y]) => new THREE.Vector2(x, y)));
      (obstacle.name.startsWith('wall ') ? walls : furniture).push(new THREE.ExtrudeGeometry(shape, { depth: obstacle.height, bevelEnabled: false }));
    }
    // A map from an image has its walls only as segments (a geometry map's are its obstacles' edges).
    if (world.obstacles.length === 0) {
      for (const wall of world.walls) {
        walls.push(slabGeometry(wall.from, wall.to, 0.08, wall.top ?? DEFAULT_WALL_HEIGHT));
      }
    }
    for (const mesh of [mergedMesh(walls, new THREE.MeshLambertMaterial({ color: colours.wall })),
      mergedMesh(furniture, new THREE.MeshLambertMaterial({ color: colours.furniture }))]) if (mesh) base.add(mesh);
    // What the scene frames draw as it stands once they come: the doors and objects as the world has them.
    this.worldMovables = new THREE.Group();
    base.add(this.worldMovables);
    this.doors = new Map();
    for (const door of world.doors) {
      const material = new THREE.MeshLambertMaterial({ color: colours.door, transparent: true, opacity: 0.9 });
      const slab = new THREE.Mesh(slabGeometry(door.from, door.to, Math.max(door.thickness, 0.04), DOOR_HEIGHT), material);
      slab.name = door.name;
      this.worldMovables.add(slab);
      this.doors.set(door.name, slab);
      this.setDoorState(door.name, door.initially_open ? 'open' : 'closed', false);
    }

    const objectMaterial = new THREE.MeshLambertMaterial({ color: colours.object });
    for (const object of world.objects) this.worldMovables.add(this.movableObject(object, objectMaterial));

    const rings = world.locations.map((location) => {
      const radius = Math.max(location.radius, 0.15);
      return new THREE.RingGeometry(radius - 0.04, radius, 40).translate(location.x, location.y, FLOOR_LIFT);
    });
    const locations = mergedMesh(rings, new THREE.MeshBasicMaterial({ color: colours.location, side: THREE.DoubleSide }));
    if (locations) base.add(locations);

    const dashed = new THREE.LineDashedMaterial({ color: colours.space, dashSize: 0.15, gapSize: 0.1 });
    const slots = [];
    for (const space of world.social_spaces) {
      const { x, y } = space.centre;
      const reach = Math.max(0.6, ...space.slots.map((slot) => Math.hypot(slot.x - x, slot.y - y) + 0.3));
      const circle = [];
      for (let i = 0; i <= 64; i++) {
        const angle = (i / 64) * 2 * Math.PI;
        circle.push([x + reach * Math.cos(angle), y + reach * Math.sin(angle)]);
      }
      const line = polyline(circle, FLOOR_LIFT, dashed);
      line.computeLineDistances();
      line.name = space.name;
      base.add(line);
      for (const slot of space.slots) slots.push(new THREE.CircleGeometry(0.07, 16).translate(slot.x, slot.y, FLOOR_LIFT));
    }
    const slotDots = mergedMesh(slots, new THREE.MeshBasicMaterial({ color: colours.space }));
    if (slotDots) base.add(slotDots);
    this.scene.add(base);
  }

  /** A movable object at its pose (that of its centre), shaped as the world gives it: a cylinder's or capsule's length is along its z. */
  movableObject({ name, shape, pose }, material) {
    const geometry = shape.kind === 'box' ? new THREE.BoxGeometry(...shape.size)
      : shape.kind === 'sphere' ? new THREE.SphereGeometry(shape.radius, 16, 12)
        : shape.kind === 'capsule' ? new THREE.CapsuleGeometry(shape.radius, shape.length, 4, 16).rotateX(Math.PI / 2)
          : new THREE.CylinderGeometry(shape.radius, shape.radius, shape.length, 20).rotateX(Math.PI / 2);
    const mesh = new THREE.Mesh(geometry, material);
    mesh.position.set(pose.x, pose.y, pose.z);
    mesh.rotation.set(pose.roll, pose.pitch, pose.yaw, 'ZYX');
    mesh.name = name;
    return mesh;
  }

  /** A door as the session reports it (`door_state` events): open doors are hidden, moving ones faint. */
  setDoorState(name, state, redraw = true) {
    const slab = this.doors.get(name);
    if (!slab) return;
    slab.visible = state !== 'open';
    slab.material.opacity = state === 'closed' ? 0.9 : 0.35;
    if (redraw) this.invalidate();
  }

  /** 'top': orthographic from above, x right and y up; 'perspective': orbit around the map with the mouse. */
  setView(view) {
    if (this.controls) {
      this.controls.removeEventListener('change', this.onChange);
      this.controls.removeEventListener('end', this.onCameraEnd);
      this.controls.dispose();
    }
    this.view = view;
    if (view === 'top') {
      this.camera = new THREE.OrthographicCamera(-1, 1, 1, -1, 0.1, 200);
      this.camera.up.set(0, 1, 0);
      this.camera.position.set(this.centre.x, this.centre.y, 50);
      this.fitCamera();
    } else {
      this.camera = new THREE.PerspectiveCamera(PERSPECTIVE_FOV, 1, 0.05, 500);
      this.camera.up.set(0, 0, 1);  // before the controls: they orbit about the camera's up
      this.fitCamera();
      // From the south, far enough that the whole map fits the frame.
      const tanV = Math.tan(THREE.MathUtils.degToRad(PERSPECTIVE_FOV) / 2);
      const distance = 1.15 * Math.max(this.span.x / (2 * tanV * this.camera.aspect), (0.8 * this.span.y) / (2 * tanV));
      this.camera.position.set(this.centre.x, this.centre.y - distance * Math.cos(PERSPECTIVE_ELEVATION),
        distance * Math.sin(PERSPECTIVE_ELEVATION));
    }
    this.camera.lookAt(this.centre);
    this.controls = new OrbitControls(this.camera, this.renderer.domElement);
    this.controls.target.copy(this.centre);
    if (view === 'top') {
      this.controls.enableRotate = false;
      this.controls.screenSpacePanning = true;
      this.controls.mouseButtons = { LEFT: THREE.MOUSE.PAN, MIDDLE: THREE.MOUSE.DOLLY, RIGHT: THREE.MOUSE.PAN };
    } else {
      this.controls.maxPolarAngle = Math.PI / 2 - 0.05;  // stay above the floor
    }
    this.controls.update();
    this.controls.addEventListener('change', this.onChange);
    this.controls.addEventListener('end', this.onCameraEnd);
    this.invalidate();
  }

  /**
   * Where the camera is, for an address: {view, position: [x, y, z], target: [x, y, z], zoom} in metres
   * in the map frame, to the centimetre (zoom: the top view's).
   */
  cameraPose() {
    const cm = (value) => Math.round(value * 100) / 100;
    return {
      view: this.view,
      position: this.camera.position.toArray().map(cm),
      target: this.controls.target.toArray().map(cm),
      zoom: cm(this.camera.zoom),
    };
  }

  /** Puts the camera where cameraPose() said it was (in that view). */
  setCameraPose({ view, position, target, zoom = 1 }) {
    if (view !== this.view) this.setView(view);
    this.camera.position.fromArray(position);
    this.controls.target.fromArray(target);
    this.camera.zoom = zoom;
    this.camera.updateProjectionMatrix();
    this.controls.update();
    this.invalidate();
  }

  /** Calls `listener(cameraPose())` each time the user has moved the camera (a drag or a zoom ended). */
  onCameraMoved(listener) {
    this.cameraListeners.push(listener);
  }

  /** The camera's projection for the canvas's shape: the top view shows the whole map. */
  fitCamera() {
    const width = Math.max(this.renderer.domElement.clientWidth, 1);
    const aspect = width / this.canvasHeight;
    if (this.camera.isOrthographicCamera) {
      const margin = 0.5;
      let halfWidth = this.span.x / 2 + margin, halfHeight = this.span.y / 2 + margin;
      if (halfWidth / halfHeight > aspect) halfHeight = halfWidth / aspect;
      else halfWidth = halfHeight * aspect;
      Object.assign(this.camera, { left: -halfWidth, right: halfWidth, top: halfHeight, bottom: -halfHeight });
    } else {
      this.camera.aspect = aspect;
    }
    this.camera.updateProjectionMatrix();
  }

  /**
   * Agents now: [{id, kind: 'human'|'robot', x, y, theta, radius, busy?}]; those left out are removed.
   * While animating, each goes there from where it is drawn.
   */
  update(agents) {
    this.agentMotion.arrive(performance.now());
    const seen = new Set();
    for (const agent of agents) {
      seen.add(agent.id);
      let entry = this.agents.get(agent.id);
      if (!entry || entry.kind !== agent.kind || entry.radius !== agent.radius) {
        if (entry) this.removeAgent(agent.id);
        entry = this.makeAgent(agent);
        this.agents.set(agent.id, entry);
        this.layers.agents.add(entry.group);
      }
      entry.from = entry.to ? { x: entry.group.position.x, y: entry.group.position.y, theta: entry.group.rotation.z } : agent;
      entry.to = { x: agent.x, y: agent.y, theta: agent.theta };
      if (agent.kind === 'human') {
        const idle = agent.busy === false;
        entry.body.material = idle ? this.shared.humanIdle : this.shared.human;
        entry.arrow.material = idle ? this.shared.humanIdleArrow : this.shared.humanArrow;
      }
    }
    for (const id of [...this.agents.keys()]) if (!seen.has(id)) this.removeAgent(id);
    this.invalidate();
  }

  /**
   * A session's scene frame (lib/scene_frame.js), the next of those that draw what moves: from the
   * first one on, people and robots are their bodies and links (their markers keep the heading and
   * name), and doors and objects stand as the frames have them.
   */
  setSceneFrame(frame) {
    this.bodyMotion.arrive(performance.now());
    this.bodies.setFrame(frame);
    this.worldMovables.visible = false;
    for (const entry of this.agents.values()) entry.solids.visible = false;
    this.invalidate();
  }

  /** On: a frame at every display refresh, moving agents and parts between poses; off: on demand again. */
  setAnimating(on) {
    this.animating = on;
    this.invalidate();
  }

  /** Puts agents, parts and the rings where they are `now` on their way (at the end when not animating). */
  #pose(now) {
    const agentProgress = this.animating ? this.agentMotion.progress(now) : 1;
    for (const entry of this.agents.values()) {
      const { from, to, group } = entry;
      if (!to) continue;
      // The shorter way round for the heading.
      const turn = Math.atan2(Math.sin(to.theta - from.theta), Math.cos(to.theta - from.theta));
      group.position.set(from.x + (to.x - from.x) * agentProgress, from.y + (to.y - from.y) * agentProgress, 0);
      group.rotation.z = from.theta + turn * agentProgress;
    }
    this.bodies.pose(this.animating ? this.bodyMotion.progress(now) : 1);
    const followed = this.agents.get(this.ringsFollow);
    if (followed) this.layers.rings.position.set(followed.group.position.x, followed.group.position.y, 0);
  }

  makeAgent({ id, kind, radius = 0.3 }) {
    const group = new THREE.Group();
    group.name = id;
    const s = this.shared;
    // Its solids until scene frames draw its body.
    const solids = new THREE.Group();
    solids.visible = !this.bodies.frame;
    let body;
    if (kind === 'human') {
      body = new THREE.Mesh(s.cylinder, s.human);
      body.scale.set(radius * 0.8, radius * 0.8, BODY_HEIGHT);
      const head = new THREE.Mesh(s.sphere, s.head);
      head.scale.setScalar(HEAD_RADIUS);
      head.position.set(0.02, 0, BODY_HEIGHT + HEAD_RADIUS + 0.02);
      solids.add(body, head);
    } else {
      body = new THREE.Mesh(s.cylinder, s.robot);
      body.scale.set(radius, radius, ROBOT_BASE_HEIGHT);
      const mast = new THREE.Mesh(s.box, s.robotDark);
      mast.scale.set(radius * 0.6, radius * 0.6, ROBOT_MAST_HEIGHT);
      mast.position.z = ROBOT_BASE_HEIGHT;
      solids.add(body, mast);
    }
    group.add(solids);
    // The heading: a flat arrow on the floor from the body's edge forwards.
    const arrow = new THREE.Mesh(s.arrow, kind === 'human' ? s.humanArrow : s.robotArrow);
    arrow.scale.set(Math.max(radius, 0.25) * 1.4, Math.max(radius, 0.25) * 0.9, 1);
    arrow.position.set(radius * 0.9, 0, FLOOR_LIFT * 2);
    group.add(arrow);
    const label = labelSprite(id, kind === 'human' ? palette.human : '#9c530c', this.labelHeight);
    label.position.set(0, 0, (kind === 'human' ? HUMAN_LABEL_HEIGHT : ROBOT_BASE_HEIGHT + ROBOT_MAST_HEIGHT + 0.35));
    group.add(label);
    return { group, solids, body, arrow, kind, radius, from: null, to: null };
  }

  removeAgent(id) {
    const entry = this.agents.get(id);
    if (!entry) return;
    this.layers.agents.remove(entry.group);
    disposeTree(entry.group);
    this.agents.delete(id);
  }

  /**
   * Polylines on the floor by key, {key: [[x, y], …] or {points, colour, dashed}} (trails, planned paths
   * ahead); others are removed.
   */
  setPaths(paths) {
    for (const line of this.paths.values()) {
      this.layers.paths.remove(line);
      disposeTree(line);
    }
    this.paths.clear();
    let index = 0;
    for (const [id, value] of Object.entries(paths)) {
      // A path is its points, or {points, colour, dashed} (a planned path ahead, say).
      const points = Array.isArray(value) ? value : value.points;
      const colour = (!Array.isArray(value) && value.colour) || palette.path[index % palette.path.length];
      index++;
      if (points.length < 2) continue;
      const dashed = !Array.isArray(value) && value.dashed;
      const line = polyline(points, FLOOR_LIFT * 1.5, this.lineMaterial(colour, dashed));
      if (dashed) line.computeLineDistances();
      line.name = `path ${id}`;
      this.layers.paths.add(line);
      this.paths.set(id, line);
    }
    this.invalidate();
  }

  /** The material of a path of `colour`, `dashed` or not (shared: see lineMaterials). */
  lineMaterial(colour, dashed) {
    const key = `${colour} ${dashed}`;
    if (!this.lineMaterials.has(key)) {
      const material = dashed ? new THREE.LineDashedMaterial({ color: colour, dashSize: 0.25, gapSize: 0.15 }) : new THREE.LineBasicMaterial({ color: colour });
      material.userData.shared = true;
      this.lineMaterials.set(key, material);
    }
    return this.lineMaterials.get(key);
  }

  /**
   * A robot's laser scan: {x, y, theta} of the sensor, angle_min, angle_increment (rad), ranges (m;
   * "inf", "-inf" or non-finite values have no return and are skipped), height (m, optional). null
   * removes it.
   */
  setLaser(robotId, scan) {
    const old = this.lasers.get(robotId);
    if (old) {
      this.layers.laser.remove(old);
      disposeTree(old);
      this.lasers.delete(robotId);
    }
    if (scan) {
      const z = scan.height ?? DEFAULT_LASER_HEIGHT;
      const points = [];
      scan.ranges.forEach((value, i) => {
        const range = Number(value);
        if (!Number.isFinite(range)) return;
        const angle = scan.theta + scan.angle_min + i * scan.angle_increment;
        points.push(new THREE.Vector3(scan.x + range * Math.cos(angle), scan.y + range * Math.sin(angle), z));
      });
      const cloud = new THREE.Points(new THREE.BufferGeometry().setFromPoints(points), this.shared.laser);
      cloud.name = `laser ${robotId}`;
      this.layers.laser.add(cloud);
      this.lasers.set(robotId, cloud);
    }
    this.invalidate();
  }

  /** Rings at Hall's distances around the agent `agentId` (the robot), following it; radii in m, null hides them. */
  setProxemicRings(agentId, radii = Object.values(PROXEMIC_DISTANCES)) {
    const rings = this.layers.rings;
    this.ringsFollow = agentId;
    if (radii === null) {
      rings.visible = false;
      this.invalidate();
      return;
    }
    const key = radii.join(',');
    if (this.ringRadii !== key) {
      for (const child of [...rings.children]) {
        rings.remove(child);
        disposeTree(child);
      }
      const names = Object.keys(PROXEMIC_DISTANCES);
      radii.forEach((radius, i) => {
        const colour = colours.proxemic[i % colours.proxemic.length];
        const ring = new THREE.Mesh(new THREE.RingGeometry(radius - 0.025, radius, 72),
          new THREE.MeshBasicMaterial({ color: colour, transparent: true, opacity: 0.7, side: THREE.DoubleSide }));
        ring.position.z = FLOOR_LIFT * 0.5;
        rings.add(ring);
        const label = labelSprite(`${names[i] ?? ''} ${radius} m`.trim(), `#${colour.getHexString()}`, this.labelHeight * 0.7);
        label.position.set(radius * Math.SQRT1_2, -radius * Math.SQRT1_2, 0.15);
        rings.add(label);
      });
      this.ringRadii = key;
    }
    rings.visible = true;
    this.invalidate();
  }

  /** The canvas's height: the view's, or the whole container's while it is full screen. */
  get canvasHeight() {
    return document.fullscreenElement === this.container ? Math.max(Math.floor(this.container.clientHeight), 1) : this.height;
  }

  /** Fits the canvas to the container's width (called by a ResizeObserver, or by the page). */
  resize() {
    if (this.disposed) return;
    const width = Math.max(Math.floor(this.container.clientWidth), 1);
    this.renderer.setSize(width, this.canvasHeight);
    this.fitCamera();
    this.invalidate();
  }

  /**
   * Asks for one frame at the next animation frame (several changes before it make one frame); while
   * animating, each frame asks for the next.
   */
  invalidate() {
    if (this.disposed || this.frameRequest) return;
    this.frameRequest = requestAnimationFrame((now) => {
      this.frameRequest = 0;
      this.#pose(now);
      this.renderer.render(this.scene, this.camera);
      this.frames += 1;
      this.container.dataset.frames = String(this.frames);
      if (this.animating) this.invalidate();
    });
  }

  /** Frees every WebGL resource and removes the canvas. */
  dispose() {
    if (this.disposed) return;
    this.disposed = true;
    cancelAnimationFrame(this.frameRequest);
    this.resizeObserver.disconnect();
    this.controls.removeEventListener('change', this.onChange);
    this.controls.removeEventListener('end', this.onCameraEnd);
    this.controls.dispose();
    this.bodies.dispose();
    disposeTree(this.scene);
    for (const item of [...Object.values(this.shared), ...this.lineMaterials.values()]) item.dispose();
    this.renderer.dispose();
    this.renderer.forceContextLoss();  // browsers cap live WebGL contexts; do not wait for garbage collection
    this.renderer.domElement.remove();
  }
}
