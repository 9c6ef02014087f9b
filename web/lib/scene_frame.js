// The binary scene frame (HRSF: api/asyncapi.yaml, message sceneFrame) the server answers to the
// WebSocket's `scene` and to GET /api/v1/sessions/{id}/scene: what moves in a session (people's body
// capsules, robots' links, objects, doors) as 48-byte records after a 32-byte header. A frame is a
// DataView of the message's bytes that reads each record in place: one allocation a frame, none a
// record.

const MAGIC = 'HRSF';
const VERSION = 1;
/** The fields of a record this page reads end here; a longer record has more after them. */
const RECORD_FIELDS_BYTES = 48;

/** A record's shape: box, cylinder (axis z) and sphere have a pose and a size; a capsule has two ends and a radius. */
export const SHAPE = Object.freeze({ box: 0, cylinder: 1, sphere: 2, capsule: 3 });

/** Instance ids (sim/scene_view.hpp), by what they belong to. */
const DOOR_ID_BASE = 2000;
const OBJECT_ID_BASE = 3000;
const AGENT_ID_BASE = 10000;
const ROBOT_LINK_ID_BASE = 1000000;

/**
 * What a part with instance `id` and `shape` is: 'door', 'object', 'person' (one of a person's 13
 * capsules), 'robot' (a robot's link, or a robot without a model as one cylinder) or 'world'.
 */
export function partKind(id, shape) {
  if (id >= ROBOT_LINK_ID_BASE) return 'robot';
  if (id >= AGENT_ID_BASE) return shape === SHAPE.capsule ? 'person' : 'robot';
  if (id >= OBJECT_ID_BASE) return 'object';
  if (id >= DOOR_ID_BASE) return 'door';
  return 'world';
}

/** The index of the agent a part of a person or robot belongs to (its index in the session), else -1. */
export function agentIndex(id) {
  if (id >= ROBOT_LINK_ID_BASE) return Math.floor((id - ROBOT_LINK_ID_BASE) / 1000);
  return id >= AGENT_ID_BASE ? id - AGENT_ID_BASE : -1;
}

export class SceneFrame extends DataView {
  /** Reads the header of `buffer` (an ArrayBuffer); throws when it is no scene frame this page reads. */
  constructor(buffer) {
    super(buffer);
    const magic = String.fromCharCode(this.getUint8(0), this.getUint8(1), this.getUint8(2), this.getUint8(3));
    if (magic !== MAGIC || this.getUint16(4, true) !== VERSION) throw new Error(`not a scene frame (${magic} version ${this.getUint16(4, true)})`);
    this.headerSize = this.getUint16(6, true);
    this.tick = Number(this.getBigInt64(8, true));
    this.time = this.getFloat64(16, true);
    this.count = this.getUint32(24, true);
    this.recordSize = this.getUint32(28, true);
    if (this.recordSize < RECORD_FIELDS_BYTES || this.headerSize + this.count * this.recordSize > buffer.byteLength) {
      throw new Error(`a scene frame of ${buffer.byteLength} bytes cannot hold ${this.count} records of ${this.recordSize}`);
    }
  }

  /** Where record `i` starts, in bytes. */
  at(i) {
    return this.headerSize + i * this.recordSize;
  }

  id(i) {
    return this.getUint32(this.at(i), true);
  }

  shape(i) {
    return this.getUint8(this.at(i) + 4);
  }

  /** Colour channel `c` (0 red, 1 green, 2 blue) of record `i`, linear, 0–1. */
  colour(i, c) {
    return this.getUint8(this.at(i) + 5 + c) / 255;
  }

  /**
   * Float `k` (0–9) of record `i`: 0–2 a (a centre, or a capsule's first end), 3–5 b (a size, or its
   * other end), 6–9 c (an orientation quaternion x, y, z, w, or the capsule's radius then zeros).
   */
  float(i, k) {
    return this.getFloat32(this.at(i) + 8 + 4 * k, true);
  }
}
