'use strict';
// The binary laser frame of the session WebSocket (api/asyncapi.yaml, message laserFrame): its layout
// as this decoder reads it, and as the spec's table says it is, so that the two can be compared.
const assert = require('node:assert/strict');
const { asyncapi } = require('./contract');

/** [offset, type, field] of every part of a frame, as decodeLaserFrame() reads them. */
const LAYOUT = [
  [0, 'char[4]', 'magic'],
  [4, 'u16', 'version'],
  [6, 'u16', 'header_size'],
  [8, 'i64', 'tick'],
  [16, 'f64', 'time'],
  [24, 'f32', 'x'],
  [28, 'f32', 'y'],
  [32, 'f32', 'theta'],
  [36, 'f32', 'angle_min'],
  [40, 'f32', 'angle_increment'],
  [44, 'f32', 'range_min'],
  [48, 'f32', 'range_max'],
  [52, 'u32', 'count'],
  [56, 'f32[]', 'ranges'],
];

const READ = {
  'char[4]': (buffer, offset) => buffer.toString('latin1', offset, offset + 4),
  u16: (buffer, offset) => buffer.readUInt16LE(offset),
  u32: (buffer, offset) => buffer.readUInt32LE(offset),
  i64: (buffer, offset) => Number(buffer.readBigInt64LE(offset)),
  f64: (buffer, offset) => buffer.readDoubleLE(offset),
  f32: (buffer, offset) => buffer.readFloatLE(offset),
};

/** The layout table in the laserFrame message's description: [offset, type, field] per row. */
function layoutInSpec() {
  const { description } = asyncapi.components.messages.laserFrame;
  return description.split('\n')
    .map((line) => /^\|\s*(\d+)\s*\|\s*(\S+)\s*\|\s*(\S+)\s*\|/.exec(line.trim()))
    .filter(Boolean)
    .map(([, offset, type, field]) => [Number(offset), type, field]);
}

/** Decodes a frame, failing unless its magic, version, header size and length are right. */
function decodeLaserFrame(buffer) {
  assert.ok(Buffer.isBuffer(buffer), 'a binary message');
  assert.ok(buffer.length >= 56, `${buffer.length} bytes: shorter than the header`);
  const frame = {};
  for (const [offset, type, field] of LAYOUT) {
    if (type !== 'f32[]') frame[field] = READ[type](buffer, offset);
  }
  assert.equal(frame.magic, 'HRLS');
  assert.equal(frame.version, 1);
  assert.equal(frame.header_size, 56);
  assert.equal(buffer.length, frame.header_size + 4 * frame.count, 'header and count × 4 bytes of ranges');
  frame.ranges = Array.from({ length: frame.count }, (_, i) => buffer.readFloatLE(frame.header_size + 4 * i));
  return frame;
}

module.exports = { LAYOUT, READ, layoutInSpec, decodeLaserFrame };
