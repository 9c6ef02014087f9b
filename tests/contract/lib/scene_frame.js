'use strict';
// The binary scene frame (api/asyncapi.yaml, message sceneFrame), read as a browser reads it: the
// header, then 48-byte records of floats at 4-byte offsets.
const assert = require('node:assert/strict');

const HEADER_SIZE = 32;
const RECORD_SIZE = 48;

/** { tick, time, parts: [{ id, shape, colour: [r, g, b], a: [3], b: [3], c: [4], radius }] } of a frame's bytes. */
function decodeSceneFrame(bytes) {
  assert.equal(bytes.toString('latin1', 0, 4), 'HRSF');
  assert.equal(bytes.readUInt16LE(4), 1, 'version');
  assert.equal(bytes.readUInt16LE(6), HEADER_SIZE);
  const count = bytes.readUInt32LE(24);
  assert.equal(bytes.readUInt32LE(28), RECORD_SIZE);
  assert.equal(bytes.length, HEADER_SIZE + count * RECORD_SIZE, 'the header\'s count of records');
  const floats = (offset, n) => Array.from({ length: n }, (_, i) => bytes.readFloatLE(offset + 4 * i));
  const parts = [];
  for (let i = 0; i < count; i += 1) {
    const at = HEADER_SIZE + i * RECORD_SIZE;
    const c = floats(at + 32, 4);
    parts.push({ id: bytes.readUInt32LE(at), shape: bytes[at + 4], colour: [bytes[at + 5], bytes[at + 6], bytes[at + 7]],
      a: floats(at + 8, 3), b: floats(at + 20, 3), c, radius: c[0] });
  }
  return { tick: Number(bytes.readBigInt64LE(8)), time: bytes.readDoubleLE(16), parts };
}

module.exports = { decodeSceneFrame };
