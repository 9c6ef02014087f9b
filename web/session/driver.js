// A live session's connection to the server: the REST calls that load and end it, and its WebSocket,
// over which the driver steps a lockstep session at the chosen speed (one step message in flight at
// most) or watches a realtime one, fetching the state, the scene frame, the robot's laser and a
// camera's frames.
// Panels render what it hears; they listen with driver.on(type, listener) to:
//   status (status)     the session's status, merged from every reply (first, the one loaded with the page)
//   events (events)     new events, each once: from step replies, or in realtime from the state
//   step (reply)        a step's reply (its reward, in a benchmark task)
//   state (state)       the agents and the open requests
//   scene (buffer)      the scene frame (HRSF) of each round's tick: what moves, for the 3D view
//   sensors (sensors)   the laser scans of the robot set by setSensors()
//   frame (buffer)      a frame (HRCF) of the camera set by setCamera(); cameraError (error) when refused
//   round ()            a round of requests starts; stepError (error) when its step failed
//   playing (boolean)   play() and pause()
//   reset (status)      reset() started the session again from tick 0, or seek() put it at another
//                       tick: trails, events and returns start over (the events up to that tick follow)
//   closed (event)      the server closed the socket
import { api, ApiError, sessionSocketUrl } from '../lib/api.js';
import { Lockstep } from './lockstep.js';

export const CAMERA_SIZE = { width: 320, height: 240 };
/** The most events the page shows; a realtime state may bring more, the older are dropped. */
export const MAX_EVENTS = 200;
/** A few camera frames a second: each is drawn off-screen on the server's worker pool. */
const CAMERA_INTERVAL_MS = 250;
const SENSORS_INTERVAL_MS = 200;
/**
 * How long the play loop waits after a round before it steps what the clock owes: about ten rounds a
 * second. The 3D view moves smoothly between rounds, and fewer rounds leave more of a slow machine to
 * drawing (in software GL, 25 rounds a second cost about a tenth of the frame rate).
 */
const LOOP_INTERVAL_MS = 80;
/** A realtime session steps itself; the page only looks at it this often, ms. */
const WATCH_INTERVAL_MS = 100;
/** Simulated time the page may owe after a slow reply (wall s × speed); more is dropped, not caught up. */
const MAX_BACKLOG_S = 0.5;

/** The session and what its page shows besides: its scenario, world, cameras, the robot's action space and the episode it replays. */
export async function loadSession(id) {
  const session = `/api/v1/sessions/${encodeURIComponent(id)}`;
  const status = await api.get(session);
  // A replay of a stored episode: the episode too, whose length the seek slider covers.
  const [world, scenario, cameras, replayed] = await Promise.all([
    api.get(`/api/v1/scenarios/${encodeURIComponent(status.scenario)}/world`),
    api.get(`/api/v1/scenarios/${encodeURIComponent(status.scenario)}`),
    api.get(`${session}/cameras`),
    status.episode ? api.get(`/api/v1/episodes/${encodeURIComponent(status.episode)}`) : null,
  ]);
  // Only a session with a robot has an action space (asked otherwise, the browser logs the 409); 409
  // also for a robot without a drive: then it cannot be driven by keys.
  const actionSpace = !world.agents.some((agent) => agent.kind === 'robot') ? null
    : await api.get(`${session}/action_space`).catch((error) => {
      if (error instanceof ApiError && error.status === 409) return null;
      throw error;
    });
  return { driver: new SessionDriver(id, status), world, scenario, cameras, actionSpace, replayed };
}

export class SessionDriver {
  /** Simulated seconds per wall-clock second while playing. */
  speed = 1;
  playing = false;
  disposed = false;
  ending = false;  // end() under way: the session is about to be gone
  #socket = null;
  #listeners = new Map();
  #camera = null;
  #sensorsOf = null;
  #debt = 0;
  #lastClock = 0;
  #timer = 0;
  #inFlight = null;
  #queuedSteps = 0;
  #stepsWaiting = false;
  #lastCamera = -Infinity;
  #lastSensors = -Infinity;
  #eventsFrom;  // the next state brings the events from this tick on (null: the step replies bring them)

  constructor(id, status) {
    this.id = id;
    this.status = status;
    this.dt = status.dt;
    this.realtime = status.mode === 'realtime';
    this.#eventsFrom = this.realtime ? 0 : null;
  }

  /** A benchmark task's step is its frame skip in ticks (docs/benchmark.md); otherwise one tick. */
  get stepTicks() {
    return this.status.task?.step_ticks ?? 1;
  }

  on(type, listener) {
    if (!this.#listeners.has(type)) this.#listeners.set(type, []);
    this.#listeners.get(type).push(listener);
  }

  #emit(type, value) {
    for (const listener of this.#listeners.get(type) ?? []) listener(value);
  }

  /** Tells the panels the status loaded with the page, then creates the socket (see start()). */
  async connect() {
    this.#applyStatus({});
    this.#socket = new Lockstep(await sessionSocketUrl(this.id), (event) => {
      this.pause();
      this.#emit('closed', event);
    });
  }

  /** Once the socket is open (rejects if it cannot open): the first state, or watching a realtime session. */
  async start() {
    await this.#socket.opened;
    if (this.realtime) this.#watch();
    else this.#refresh();
  }

  dispose() {
    this.disposed = true;
    this.playing = false;
    clearTimeout(this.#timer);
    if (this.#socket) this.#socket.close();
  }

  /** Ends the session on the server; rejects (and stays connected) when it refuses. */
  async end() {
    this.pause();
    this.ending = true;  // panels that poll the session stop asking
    if (this.#socket) this.#socket.closing = true;  // the server closes the socket: that is no error here
    try {
      await api.delete(`/api/v1/sessions/${encodeURIComponent(this.id)}`);
    } catch (error) {
      this.ending = false;
      if (this.#socket) this.#socket.closing = false;
      throw error;
    }
  }

  /** Sends one command (a robot's velocity or request, a human's command); resolves with the reply. */
  command(command) {
    if (!this.#socket) return Promise.reject(new Error('not connected to the session'));
    return this.#socket.send({ type: 'commands', commands: [command] });
  }

  /** The camera whose frames each round fetches (null: none); fetches one now. */
  setCamera(name) {
    this.#camera = name;
    this.#lastCamera = -Infinity;
    this.#refresh();
  }

  /** The robot whose laser each round fetches (null: none); fetches the state and the laser now. */
  setSensors(robotId) {
    this.#sensorsOf = robotId;
    this.#lastSensors = -Infinity;
    this.#refresh();
  }

  play() {
    if (this.status.status === 'finished' || !this.#socket) return;
    this.playing = true;
    this.#debt = 0;
    this.#lastClock = performance.now();
    clearTimeout(this.#timer);
    this.#emit('playing', true);
    this.#loop();
  }

  pause() {
    if (this.realtime) return;  // the server plays it: the page's watching goes on (#timer is the watch's)
    const wasPlaying = this.playing;
    this.playing = false;
    clearTimeout(this.#timer);
    this.#emit('playing', false);
    if (wasPlaying) {
      // The camera and laser are throttled while playing: bring them up to the tick it stopped at.
      this.#lastCamera = -Infinity;
      this.#lastSensors = -Infinity;
      (this.#inFlight ?? Promise.resolve()).then(() => this.#refresh());
    }
  }

  /**
   * Starts the session again from tick 0 with its own seed (POST …/reset), paused, then fetches the
   * fresh state, laser and camera. Rejects when the server refuses.
   */
  async reset() {
    await this.#startOver(async () => {
      // The reply is the fresh status with Gymnasium's first observation and info, which no panel shows.
      const { observation, info, ...status } = await api.post(`/api/v1/sessions/${encodeURIComponent(this.id)}/reset`, { seed: this.status.seed });
      return { status, eventsFrom: this.realtime ? 0 : null };
    });
  }

  /**
   * Puts the session at `tick` (the WebSocket's seek): back, the state it had then bit for bit; forth
   * (lockstep only), the ticks a clock gives. Paused, then the state with every event up to the tick,
   * the laser and the camera. Rejects when the server refuses.
   */
  async seek(tick) {
    await this.#startOver(async () => {
      const { type, observation, info, ...status } = await this.#socket.send({ type: 'seek', tick });
      // Step replies bring only the events after the tick: the earlier ones come with the next state.
      return { status, eventsFrom: 0 };
    });
  }

  /**
   * A reset or a seek: `move()` asks the server and resolves with the new status and where the next
   * state's events start. It is the round in flight meanwhile: no step or state goes out before it
   * lands (one sent during it would land on either side of it).
   */
  async #startOver(move) {
    this.pause();
    this.#queuedSteps = 0;
    while (this.#inFlight) await this.#inFlight;  // the step in flight lands before the move, not after it
    const moved = move().then(({ status, eventsFrom }) => {
      this.#eventsFrom = eventsFrom;
      this.#applyStatus(status);
      this.#emit('reset', this.status);
    });
    this.#inFlight = moved.catch(() => {}).finally(() => { this.#inFlight = null; });
    await moved;
    await this.#inFlight;
    this.#lastCamera = -Infinity;
    this.#lastSensors = -Infinity;
    this.#refresh();
  }

  /** One step per call; calls while a reply is awaited are added up and sent together after it. */
  step() {
    if (this.status.status === 'finished' || this.playing) return;
    this.#queuedSteps += 1;
    this.#sendSteps();
  }

  #sendSteps() {
    if (this.#inFlight) {
      if (!this.#stepsWaiting) {
        this.#stepsWaiting = true;
        this.#inFlight.then(() => {
          this.#stepsWaiting = false;
          this.#sendSteps();
        });
      }
      return;
    }
    if (!this.#queuedSteps || this.playing || this.disposed) return;
    this.#lastCamera = -Infinity;
    this.#lastSensors = -Infinity;
    const n = this.#queuedSteps;
    this.#queuedSteps = 0;
    this.#cycle(n).then(() => this.#sendSteps());
  }

  /** Steps as many ticks as the wall clock × speed owes, one step message at a time. */
  #loop() {
    this.#timer = 0;
    if (!this.playing || this.disposed) return;
    const now = performance.now();
    this.#debt = Math.min(this.#debt + ((now - this.#lastClock) / 1000) * this.speed, MAX_BACKLOG_S * this.speed);
    this.#lastClock = now;
    const n = Math.floor(this.#debt / (this.dt * this.stepTicks) + 1e-6);
    if (n >= 1 && !this.#inFlight) {
      this.#debt -= n * this.dt * this.stepTicks;
      this.#cycle(n).finally(() => {
        if (this.playing && !this.disposed) this.#timer = setTimeout(() => this.#loop(), LOOP_INTERVAL_MS);
      });
    } else {
      this.#timer = setTimeout(() => this.#loop(), LOOP_INTERVAL_MS);
    }
  }

  /** A realtime session: its state, laser and camera, over and over. */
  #watch() {
    this.#timer = 0;
    if (this.disposed || !this.#socket.open) return;
    (this.#inFlight ?? this.#cycle(0)).finally(() => {
      if (!this.disposed) this.#timer = setTimeout(() => this.#watch(), WATCH_INTERVAL_MS);
    });
  }

  /** A new state, laser and camera frame without stepping (after a change of camera or layer). */
  #refresh() {
    if (!this.#inFlight && !this.playing && !this.disposed && this.#socket?.open) this.#cycle(0);
  }

  /**
   * One round: n steps (0: none), then the state and the scene frame, and the laser and camera when
   * they are due — sent together (the answers come in order), applied as each answer arrives.
   */
  #cycle(n) {
    const socket = this.#socket;
    const now = performance.now();
    const work = [];
    this.#emit('round');
    if (n > 0) {
      work.push(socket.send({ type: 'step', n }).then((reply) => {
        this.#applyStatus(reply);
        this.#emitEvents(reply.events);
        this.#emit('step', reply);
      }, (error) => {
        this.pause();
        this.#emit('stepError', error);
      }));
    }
    // In lockstep the step replies bring every event once; the state brings them only after a seek.
    const since = this.#eventsFrom;
    work.push(socket.send({ type: 'state', events_since: since ?? Number.MAX_SAFE_INTEGER }).then((state) => this.#applyState(state, since !== null), () => {}));
    work.push(socket.send({ type: 'scene' }).then((frame) => this.#emit('scene', frame), () => {}));
    if (this.#sensorsOf && now - this.#lastSensors >= SENSORS_INTERVAL_MS) {
      this.#lastSensors = now;
      work.push(socket.send({ type: 'sensors', robot: this.#sensorsOf }).then((sensors) => this.#emit('sensors', sensors), () => {}));
    }
    if (this.#camera && now - this.#lastCamera >= CAMERA_INTERVAL_MS) {
      this.#lastCamera = now;
      work.push(socket.send({ type: 'camera', camera: this.#camera, ...CAMERA_SIZE })
        .then((frame) => this.#emit('frame', frame), (error) => this.#emit('cameraError', error)));
    }
    this.#inFlight = Promise.all(work).finally(() => { this.#inFlight = null; });
    return this.#inFlight;
  }

  #applyStatus(next) {
    this.status = { ...this.status, ...next };
    if (this.status.status === 'finished') this.pause();
    this.#emit('status', this.status);
  }

  /** `withEvents`: the state was asked for the events from #eventsFrom on. */
  #applyState(state, withEvents) {
    this.#applyStatus(state);
    if (withEvents) {
      this.#emitEvents(state.events.slice(-MAX_EVENTS));
      this.#eventsFrom = this.realtime ? state.tick + 1 : null;
    }
    this.#emit('state', state);
  }

  #emitEvents(events) {
    if (events?.length) this.#emit('events', events);
  }
}
