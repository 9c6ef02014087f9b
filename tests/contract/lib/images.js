'use strict';
// Decoders for the images GET /api/v1/sessions/{id}/frames/{camera} answers (api/openapi.yaml):
// PNG (8-bit RGBA and 16-bit greyscale, non-interlaced, as the server writes them), the size of a
// JPEG, and NumPy's .npy format 1.0. Each fails on anything but a well-formed file.
const assert = require('node:assert/strict');
const zlib = require('node:zlib');

const PNG_SIGNATURE = Buffer.from([0x89, 0x50, 0x4e, 0x47, 0x0d, 0x0a, 0x1a, 0x0a]);

// CRC-32 as PNG has it (ISO 3309; zlib.crc32 needs Node 20.15, package.json allows 18).
const CRC_TABLE = Uint32Array.from({ length: 256 }, (_, n) => {
  let c = n;
  for (let k = 0; k < 8; k++) c = c & 1 ? 0xedb88320 ^ (c >>> 1) : c >>> 1;
  return c >>> 0;
});
function crc32(bytes) {
  let c = 0xffffffff;
  for (const byte of bytes) c = CRC_TABLE[(c ^ byte) & 0xff] ^ (c >>> 8);
  return (c ^ 0xffffffff) >>> 0;
}

/** Paeth predictor (PNG spec §9.4). */
function paeth(a, b, c) {
  const p = a + b - c;
  const pa = Math.abs(p - a), pb = Math.abs(p - b), pc = Math.abs(p - c);
  return pa <= pb && pa <= pc ? a : pb <= pc ? b : c;
}

/**
 * A PNG's header and samples: { width, height, bitDepth, colourType, channels, samples } with one
 * number per channel per pixel, row-major from the top row (16-bit samples big-endian, as PNG has them).
 */
function decodePng(buffer) {
  assert.ok(Buffer.isBuffer(buffer), 'a PNG is bytes');
  assert.deepEqual(buffer.subarray(0, 8), PNG_SIGNATURE, 'the PNG signature');
  let at = 8;
  let header;
  const data = [];
  let ended = false;
  while (at < buffer.length) {
    const length = buffer.readUInt32BE(at);
    const type = buffer.toString('latin1', at + 4, at + 8);
    const body = buffer.subarray(at + 8, at + 8 + length);
    assert.equal(body.length, length, `PNG chunk ${type} runs past the end`);
    assert.equal(buffer.readUInt32BE(at + 8 + length), crc32(buffer.subarray(at + 4, at + 8 + length)), `PNG chunk ${type}: CRC`);
    if (type === 'IHDR') {
      header = { width: body.readUInt32BE(0), height: body.readUInt32BE(4), bitDepth: body[8], colourType: body[9], interlace: body[12] };
    } else if (type === 'IDAT') {
      data.push(body);
    } else if (type === 'IEND') {
      ended = true;
    }
    at += 12 + length;
  }
  assert.ok(header, 'PNG: an IHDR chunk');
  assert.ok(ended, 'PNG: an IEND chunk');
  assert.equal(header.interlace, 0, 'PNG: not interlaced');
  const channels = { 0: 1, 2: 3, 4: 2, 6: 4 }[header.colourType];
  assert.ok(channels, `PNG colour type ${header.colourType}`);
  assert.ok([8, 16].includes(header.bitDepth), `PNG bit depth ${header.bitDepth}`);
  const bytesPerSample = header.bitDepth / 8;
  const pixelBytes = channels * bytesPerSample;
  const rowBytes = header.width * pixelBytes;
  const raw = zlib.inflateSync(Buffer.concat(data));
  assert.equal(raw.length, header.height * (1 + rowBytes), 'PNG: the image data is height rows of a filter byte and width pixels');
  const pixels = Buffer.alloc(header.height * rowBytes);
  for (let y = 0; y < header.height; y++) {
    const filter = raw[y * (1 + rowBytes)];
    const line = raw.subarray(y * (1 + rowBytes) + 1, (y + 1) * (1 + rowBytes));
    const out = pixels.subarray(y * rowBytes, (y + 1) * rowBytes);
    const previous = y > 0 ? pixels.subarray((y - 1) * rowBytes, y * rowBytes) : Buffer.alloc(rowBytes);
    for (let x = 0; x < rowBytes; x++) {
      const a = x >= pixelBytes ? out[x - pixelBytes] : 0;
      const b = previous[x];
      const c = x >= pixelBytes ? previous[x - pixelBytes] : 0;
      const predictor = [0, a, b, (a + b) >> 1, paeth(a, b, c)][filter];
      assert.ok(predictor !== undefined, `PNG: filter type ${filter}`);
      out[x] = (line[x] + predictor) & 0xff;
    }
  }
  const count = header.width * header.height * channels;
  const samples = bytesPerSample === 1 ? Uint8Array.from(pixels) : Uint16Array.from({ length: count }, (_, i) => pixels.readUInt16BE(2 * i));
  return { width: header.width, height: header.height, bitDepth: header.bitDepth, colourType: header.colourType, channels, samples };
}

/** A baseline or progressive JPEG's size, from its start-of-frame segment: { width, height, components }. */
function jpegSize(buffer) {
  assert.ok(Buffer.isBuffer(buffer), 'a JPEG is bytes');
  assert.deepEqual([buffer[0], buffer[1]], [0xff, 0xd8], 'the JPEG start of image');
  assert.deepEqual([buffer.at(-2), buffer.at(-1)], [0xff, 0xd9], 'the JPEG end of image');
  let at = 2;
  while (at + 4 <= buffer.length) {
    assert.equal(buffer[at], 0xff, `JPEG: a marker at ${at}`);
    const marker = buffer[at + 1];
    const length = buffer.readUInt16BE(at + 2);
    if (marker >= 0xc0 && marker <= 0xc2) {
      return { height: buffer.readUInt16BE(at + 5), width: buffer.readUInt16BE(at + 7), components: buffer[at + 9] };
    }
    at += 2 + length;
  }
  return assert.fail('JPEG: no start of frame');
}

const NPY_TYPES = { '|u1': Uint8Array, '<f4': Float32Array, '<u4': Uint32Array };

/**
 * A .npy file (format 1.0, little-endian, C order, data 64-byte aligned):
 * { descr, shape, values } with the values as a typed array of the dtype.
 */
function decodeNpy(buffer) {
  assert.ok(Buffer.isBuffer(buffer), 'a .npy file is bytes');
  assert.equal(buffer.toString('latin1', 0, 6), '\x93NUMPY', 'the .npy magic');
  assert.deepEqual([buffer[6], buffer[7]], [1, 0], '.npy format version 1.0');
  const headerLength = buffer.readUInt16LE(8);
  const start = 10 + headerLength;
  assert.equal(start % 64, 0, '.npy: the data starts 64-byte aligned');
  const header = buffer.toString('latin1', 10, start);
  assert.ok(header.endsWith('\n'), '.npy: the header ends in a newline');
  const dict = /^\{'descr': '([^']+)', 'fortran_order': (True|False), 'shape': \(([\d, ]*)\), \} *\n$/.exec(header);
  assert.ok(dict, `.npy header ${JSON.stringify(header)}`);
  const [, descr, fortranOrder, shapeText] = dict;
  assert.equal(fortranOrder, 'False', '.npy: C order');
  const shape = shapeText.split(',').map((n) => n.trim()).filter(Boolean).map(Number);
  const Type = NPY_TYPES[descr];
  assert.ok(Type, `.npy dtype ${descr}`);
  const count = shape.reduce((product, n) => product * n, 1);
  assert.equal(buffer.length - start, count * Type.BYTES_PER_ELEMENT, `.npy: ${shape.join('×')} values of ${descr}`);
  const data = buffer.subarray(start);
  const values = new Type(data.buffer.slice(data.byteOffset, data.byteOffset + data.length));
  return { descr, shape, values };
}

module.exports = { decodePng, jpegSize, decodeNpy };
