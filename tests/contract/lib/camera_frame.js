'use strict';
// The binary camera frame of the session WebSocket (api/asyncapi.yaml, message cameraFrame): its layout
// as this decoder reads it, and as the spec's table says it is, so that the two can be compared.
const assert = require('node:assert/strict');
const { asyncapi } = require('./contract');
const { READ } = require('./laser_frame');

const HEADER_SIZE = 96;
const NAME_BYTES = 36;
const PARTS = { colour: 1, depth: 2, ids: 4 };

/**
 * [offset, type, field] of every part of a frame, as decodeCameraFrame() reads them; the images'
 * offsets in terms of the image's pixels, wh = width × height.
 */
const LAYOUT = [
  ['0', 'char[4]', 'magic'],
  ['4', 'u16', 'version'],
  ['6', 'u16', 'header_size'],
  ['8', 'i64', 'tick'],
  ['16', 'f64', 'time'],
  ['24', 'u32', 'width'],
  ['28', 'u32', 'height'],
  ['32', 'f32', 'fx'],
  ['36', 'f32', 'fy'],
  ['40', 'f32', 'cx'],
  ['44', 'f32', 'cy'],
  ['48', 'f32', 'near'],
  ['52', 'f32', 'far'],
  ['56', 'u32', 'parts'],
  ['60', 'char[36]', 'camera'],
  ['96', 'u8[]', 'colour'],
  ['96 + 4wh', 'f32[]', 'depth'],
  ['96 + 8wh', 'u32[]', 'ids'],
];

/** The layout table in the cameraFrame message's description: [offset, type, field] per row. */
function layoutInSpec() {
  const { description } = asyncapi.components.messages.cameraFrame;
  return description.split('\n')
    .map((line) => /^\|\s*(\d[^|]*?)\s*\|\s*(\S+)\s*\|\s*(\S+)\s*\|/.exec(line.trim()))
    .filter(Boolean)
    .map(([, offset, type, field]) => [offset, type, field]);
}

/** `count` values of a typed array type from `buffer` at `offset` (a copy: the offset need not be aligned). */
function arrayAt(Type, buffer, offset, count) {
  const bytes = buffer.subarray(offset, offset + count * Type.BYTES_PER_ELEMENT);
  return new Type(bytes.buffer.slice(bytes.byteOffset, bytes.byteOffset + bytes.length));
}

/**
 * Decodes a frame, failing unless its magic, version, header size, parts, name padding and length are
 * right. The images come as typed arrays: colour (Uint8Array, RGBA), depth (Float32Array), ids
 * (Uint32Array, only when the frame has them).
 */
function decodeCameraFrame(buffer) {
  assert.ok(Buffer.isBuffer(buffer), 'a binary message');
  assert.ok(buffer.length >= HEADER_SIZE, `${buffer.length} bytes: shorter than the header`);
  const frame = {};
  for (const [offset, type, field] of LAYOUT.filter(([, type]) => READ[type])) frame[field] = READ[type](buffer, Number(offset));
  assert.equal(frame.magic, 'HRCF');
  assert.equal(frame.version, 1);
  assert.equal(frame.header_size, HEADER_SIZE);
  assert.ok([PARTS.colour | PARTS.depth, PARTS.colour | PARTS.depth | PARTS.ids].includes(frame.parts), `parts ${frame.parts}: colour and depth, with or without ids`);
  const name = buffer.subarray(60, 60 + NAME_BYTES);
  const end = name.indexOf(0);
  assert.ok(end > 0 && end < NAME_BYTES, 'the camera\'s name, NUL-terminated within 36 bytes');
  assert.ok(name.subarray(end).every((byte) => byte === 0), 'the name is NUL-padded');
  frame.camera = new TextDecoder('utf-8', { fatal: true }).decode(name.subarray(0, end));
  const pixels = frame.width * frame.height;
  const withIds = (frame.parts & PARTS.ids) !== 0;
  assert.equal(buffer.length, frame.header_size + pixels * (withIds ? 12 : 8), `header and ${withIds ? 12 : 8} bytes a pixel`);
  frame.colour = arrayAt(Uint8Array, buffer, frame.header_size, 4 * pixels);
  frame.depth = arrayAt(Float32Array, buffer, frame.header_size + 4 * pixels, pixels);
  if (withIds) frame.ids = arrayAt(Uint32Array, buffer, frame.header_size + 8 * pixels, pixels);
  return frame;
}

module.exports = { LAYOUT, layoutInSpec, decodeCameraFrame };
