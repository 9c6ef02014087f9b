// The session's 3D scene (three.js, lib/scene.js): people's bodies, robots' links, objects and doors as
// each round's scene frame has them, moving smoothly between rounds while the session plays; each
// agent's heading, name, trail and planned path as the driver's states give them; the robot's laser
// and proxemic rings; the legend with the toggles of those layers, and full screen.
import { h } from '../lib/ui.js';
import { SceneView, PROXEMIC_DISTANCES } from '../lib/scene.js';
import { SceneFrame } from '../lib/scene_frame.js';
import { palette } from '../lib/map2d.js';

/** Trails: the last seconds of each agent's positions, a point every few centimetres. */
const TRAIL_SECONDS = 10;
const TRAIL_SPACING_M = 0.05;

export class SessionScene {
  #driver;
  #world;
  #robot;
  #view = null;
  #layers;
  #trails = new Map();
  #laserKeys = new Set();
  #radii;

  /** `robot` is the robot under test (or null); `drivable` says its keys drive it, for the box's label. */
  constructor(driver, { world, robot, drivable }) {
    this.#driver = driver;
    this.#world = world;
    this.#robot = robot;
    this.#radii = Object.fromEntries(world.agents.map((agent) => [agent.id, agent.radius]));
    this.#layers = { laser: Boolean(robot?.model), rings: Boolean(robot), trails: true, plans: true };
    const fullScreen = h('button', {
      type: 'button', class: 'secondary scene-fullscreen', 'aria-pressed': 'false', hidden: !document.fullscreenEnabled,
      onclick: () => (document.fullscreenElement === this.box ? document.exitFullscreen() : this.box.requestFullscreen()).catch(() => {}),
    }, 'Full screen');
    /** Where the scene draws (the driving keys are heard on the whole page: teleop.js). */
    this.box = h('div', {
      class: 'scene-box', tabindex: '0', role: 'application',
      'aria-label': `3D view of ${world.name}. Drag to move the view, scroll to zoom${drivable ? '; with teleop on, arrow keys or W A S D drive the robot' : ''}; Escape leaves full screen.`,
    }, fullScreen);
    this.box.addEventListener('fullscreenchange', () => {
      fullScreen.setAttribute('aria-pressed', String(document.fullscreenElement === this.box));
      this.#view.resize();
    });
    // Browsers leave full screen on Escape themselves; this is for those that pass the key on.
    this.box.addEventListener('keydown', (event) => {
      if (event.key === 'Escape' && document.fullscreenElement === this.box) document.exitFullscreen().catch(() => {});
    });
    // Read-only, for tests and debugging: the last scene frame's parts (lib/scene_bodies.js summary()).
    this.box.sceneSummary = () => this.#view?.bodies.summary() ?? null;
    this.box.cameraPose = () => this.#view?.cameraPose() ?? null;
    const layerToggles = [
      ['trails', 'Trails (last 10 s)', true],
      ['plans', 'Planned paths (dashed)', true],
      ['laser', 'Laser scan', Boolean(robot?.model)],
      ['rings', `Proxemic rings (${Object.entries(PROXEMIC_DISTANCES).map(([name, r]) => `${name} ${r} m`).join(', ')})`, Boolean(robot)],
    ].filter(([, , available]) => available).map(([key, text]) => h('label', { class: 'check' },
      h('input', { type: 'checkbox', checked: this.#layers[key], onchange: (event) => this.#setLayer(key, event.target.checked) }), text));
    const legend = h('div', { class: 'scene-legend' },
      h('span', { class: 'ss-swatch human' }, 'human (pale arrow: idle)'), h('span', { class: 'ss-swatch robot' }, 'robot'),
      h('span', { class: 'ss-swatch location' }, 'location'), h('span', { class: 'ss-swatch space' }, 'social space'),
      world.objects.length ? h('span', { class: 'ss-swatch object' }, 'movable object') : null,
      robot?.model ? h('span', { class: 'ss-swatch laser' }, 'laser') : null, layerToggles);
    this.panel = h('section', { class: 'panel scene-panel', 'aria-label': 'Scene' }, this.box, legend);

    driver.setSensors(this.#laserRobot());
    // After a reset or a seek (forth as well) the trails start again where the agents are.
    driver.on('reset', () => this.#trails.clear());
    driver.on('state', (state) => this.#showState(state));
    driver.on('scene', (buffer) => this.#view.setSceneFrame(new SceneFrame(buffer)));
    driver.on('playing', (playing) => this.#view.setAnimating(playing));
    driver.on('sensors', (sensors) => this.#showSensors(sensors));
    driver.on('events', (events) => {
      for (const event of events) if (event.kind === 'door_state') this.#view.setDoorState(event.subject, event.data.state);
    });
  }

  /** Draws the world: once the panel is in the page, whose width the view fills. */
  mount() {
    this.#view = new SceneView(this.box, this.#world, { height: 480 });
    // A realtime session plays on the server whatever the page does.
    this.#view.setAnimating(this.#driver.realtime);
  }

  /** 'top' or 'perspective'. */
  setView(view) {
    this.#view.setView(view);
  }

  /** The view and where its camera is (lib/scene.js cameraPose()). */
  cameraPose() {
    return this.#view.cameraPose();
  }

  setCameraPose(pose) {
    this.#view.setCameraPose(pose);
  }

  /** `listener(pose)` after each move of the camera by the user. */
  onCameraMoved(listener) {
    this.#view.onCameraMoved(listener);
  }

  dispose() {
    if (this.#view) this.#view.dispose();
  }

  /** Only a robot with a model has a laser. */
  #laserRobot() {
    return this.#robot?.model && this.#layers.laser ? this.#robot.id : null;
  }

  #setLayer(key, on) {
    this.#layers = { ...this.#layers, [key]: on };
    if ((key === 'trails' || key === 'plans') && !on) this.#view.setPaths({});
    if (key === 'laser' && !on) for (const laser of this.#laserKeys) this.#view.setLaser(laser, null);
    if (key === 'rings' && !on) this.#view.setProxemicRings(null, null);
    // Any layer redraws from a fresh state and laser.
    this.#driver.setSensors(this.#laserRobot());
  }

  #showState(state) {
    const agents = state.agents.filter((agent) => agent.active).map((agent) => ({ ...agent, radius: this.#radii[agent.id] }));
    this.#view.update(agents);
    if (this.#robot && this.#layers.rings) this.#view.setProxemicRings(this.#robot.id);
    this.#updateTrails(state);
  }

  #updateTrails(state) {
    const time = this.#driver.status.time;
    for (const agent of state.agents) {
      let trail = this.#trails.get(agent.id);
      if (!trail) this.#trails.set(agent.id, (trail = []));
      const last = trail[trail.length - 1];
      if (last && time < last.t) trail.length = 0;  // another client reset the session or took it back
      if (!last || Math.hypot(agent.x - last.x, agent.y - last.y) >= TRAIL_SPACING_M) trail.push({ x: agent.x, y: agent.y, t: time });
      while (trail.length && time - trail[0].t > TRAIL_SECONDS) trail.shift();
    }
    const paths = {};
    state.agents.forEach((agent, index) => {
      // One colour per agent for its trail behind and its planned path ahead.
      const colour = palette.path[index % palette.path.length];
      const trail = this.#trails.get(agent.id);
      if (this.#layers.trails && trail) paths[`trail ${agent.id}`] = { points: [...trail.map((p) => [p.x, p.y]), [agent.x, agent.y]], colour };
      if (this.#layers.plans && agent.path.length > 1) paths[`plan ${agent.id}`] = { points: agent.path, colour, dashed: true };
    });
    this.#view.setPaths(paths);
  }

  #showSensors(sensors) {
    if (!this.#layers.laser) return;
    for (const laser of sensors.lasers) {
      if (laser.tick < 0) continue;
      const key = `${sensors.robot}/${laser.sensor}`;
      this.#laserKeys.add(key);
      this.#view.setLaser(key, { ...laser.pose, angle_min: laser.angle_min,
        angle_increment: laser.angle_increment, ranges: laser.ranges, height: laser.height });
    }
  }
}
