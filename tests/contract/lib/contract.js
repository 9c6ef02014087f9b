'use strict';
// The API descriptions (api/openapi.yaml, api/asyncapi.yaml) as checks on what the server sends, and
// the record of which operations the tests have seen succeed.
const assert = require('node:assert/strict');
const fs = require('node:fs');
const path = require('node:path');
const YAML = require('yaml');
const Ajv2020 = require('ajv/dist/2020');
const addFormats = require('ajv-formats');

const repoRoot = path.resolve(__dirname, '../../..');
const openapi = YAML.parse(fs.readFileSync(path.join(repoRoot, 'api/openapi.yaml'), 'utf8'));
const asyncapi = YAML.parse(fs.readFileSync(path.join(repoRoot, 'api/asyncapi.yaml'), 'utf8'));

// Both documents are added whole under their file names, so a schema is named by its JSON pointer
// (openapi.yaml#/components/...), its own "#/components/..." references resolve inside its document
// and asyncapi.yaml's "openapi.yaml#/..." ones in the other, as they do for tools reading the files.
// OpenAPI 3.1 schemas are JSON Schema 2020-12: OpenAPI 3.0's `nullable` and `example` are refused
// (Ajv would accept `nullable` by itself), and strict mode catches misspelt keywords. The documents'
// top-level keys (paths, channels, ...) are no schema keywords; they are declared as annotations.
// `format: binary` marks the binary WebSocket message, whose bytes no JSON schema checks.
const ajv = new Ajv2020({ strict: true, allErrors: true });
addFormats(ajv);
ajv.addFormat('binary', true);
ajv.removeKeyword('nullable');
for (const keyword of new Set([...Object.keys(openapi), ...Object.keys(asyncapi)])) {
  if (!ajv.getKeyword(keyword)) ajv.addKeyword(keyword);
}
ajv.addSchema(openapi, 'openapi.yaml');
ajv.addSchema(asyncapi, 'asyncapi.yaml');

const escapePointer = (key) => key.replace(/~/g, '~0').replace(/\//g, '~1');
const unescapePointer = (key) => key.replace(/~1/g, '/').replace(/~0/g, '~');

/** The node at `pointer` ("#/a/b") in `document`, following $refs; with the pointer it was found at. */
function follow(document, pointer) {
  let node = pointer.slice(2).split('/').map(unescapePointer).reduce((at, key) => at?.[key], document);
  while (node?.$ref) {
    pointer = node.$ref;
    node = pointer.slice(2).split('/').map(unescapePointer).reduce((at, key) => at?.[key], document);
  }
  assert.ok(node !== undefined, `the spec has nothing at ${pointer}`);
  return { node, pointer };
}

/** Fails with every schema error when `value` does not match the schema at `documentId` + `pointer`. */
function checkSchema(documentId, pointer, value, what) {
  const validate = ajv.getSchema(documentId + pointer);
  assert.ok(validate, `no schema at ${documentId}${pointer}`);
  if (!validate(value)) {
    const errors = validate.errors.map((e) => `  ${e.instancePath || '(root)'} ${e.message} ${JSON.stringify(e.params)}`);
    assert.fail(`${what} does not match ${documentId}${pointer}:\n${errors.join('\n')}\n  value: ${JSON.stringify(value).slice(0, 2000)}`);
  }
}

// --- HTTP (OpenAPI) ---

const HTTP_METHODS = ['get', 'put', 'post', 'delete', 'patch', 'head', 'options'];

const httpOperations = Object.entries(openapi.paths).flatMap(([template, item]) =>
  HTTP_METHODS.filter((method) => item[method]).map((method) => ({
    key: `${method.toUpperCase()} ${template}`,
    method: method.toUpperCase(),
    template,
    segments: template.split('/').slice(1),
    pointer: `#/paths/${escapePointer(template)}/${method}`,
    operation: item[method],
    // A server started with a token wants it on every operation whose security names `bearer`.
    needsToken: (item[method].security ?? openapi.security ?? []).some((requirement) => 'bearer' in requirement),
  })));

const isParameter = (segment) => segment.startsWith('{') && segment.endsWith('}');

/** The operation that `method` on `pathname` is, preferring literal segments ("validate") over parameters. */
function findOperation(method, pathname) {
  const segments = pathname.split('/').slice(1);
  // Outside /api/, any path of any depth is a UI file (/{path} in the spec).
  if (segments.length > 1 && segments[0] !== 'api') return findOperation(method, '/file');
  const matches = httpOperations.filter((operation) => operation.method === method &&
    operation.segments.length === segments.length &&
    operation.segments.every((expected, i) => (isParameter(expected) ? segments[i] !== '' : expected === segments[i])));
  const parameters = (operation) => operation.segments.filter(isParameter).length;
  return matches.sort((a, b) => parameters(a) - parameters(b))[0];
}

const mediaTypeOf = (headers) => (headers['content-type'] ?? '').split(';')[0].trim().toLowerCase();

const covered = new Set();

/**
 * Checks one HTTP exchange against the spec: the operation must list the status (or a `default`), the
 * content type must be one the response declares, a JSON body must match its schema, required headers
 * must be there. A request the server accepted must also be one the spec allows (a spec stricter than
 * the server fails here). A path or method the spec does not have may only answer the documented JSON
 * error. Returns the operation, or undefined.
 */
function checkHttpExchange(request, reply) {
  const what = `${request.method} ${request.target} → ${reply.status}`;
  const operation = findOperation(request.method, request.target.split('?')[0]);
  if (!operation) {
    assert.ok(reply.status >= 400 && reply.status < 500, `${what}: not in the spec, yet not a client error`);
    assert.equal(mediaTypeOf(reply.headers), 'application/json', `${what}: content type`);
    checkSchema('openapi.yaml', '#/components/schemas/Error', JSON.parse(reply.body), what);
    return undefined;
  }
  const responses = operation.operation.responses;
  const code = [String(reply.status), 'default'].find((candidate) => candidate in responses);
  assert.ok(code, `${what}: ${operation.key} lists only ${Object.keys(responses).join(', ')}; body ${reply.body.slice(0, 500)}`);
  const { node: response, pointer } = follow(openapi, `${operation.pointer}/responses/${code}`);
  for (const [name, header] of Object.entries(response.headers ?? {})) {
    if (header.required) assert.ok(reply.headers[name.toLowerCase()] !== undefined, `${what}: header ${name} is missing`);
  }
  if (reply.status === 204) assert.equal(reply.body, '', `${what}: a 204 has no body`);
  if (response.content) {
    const mediaType = mediaTypeOf(reply.headers);
    assert.ok(mediaType in response.content, `${what}: content type '${mediaType}', the spec says ${Object.keys(response.content)}`);
    if (mediaType === 'application/json' && response.content[mediaType].schema) {
      checkSchema('openapi.yaml', `${pointer}/content/application~1json/schema`, JSON.parse(reply.body), what);
    }
  }
  if (reply.status < 300 && request.json !== undefined && operation.operation.requestBody) {
    const { pointer: body } = follow(openapi, `${operation.pointer}/requestBody`);
    checkSchema('openapi.yaml', `${body}/content/application~1json/schema`, request.json, `${what}: the request the server accepted`);
  }
  if (reply.status < 300) covered.add(operation.key);
  return operation;
}

/**
 * Whether the spec allows `json` as the body of `method` on `target`: a request the server refuses
 * for its form (not for what it names) should be one the spec refuses too.
 */
function specAllows(method, target, json) {
  const operation = findOperation(method, target.split('?')[0]);
  assert.ok(operation?.operation.requestBody, `${method} ${target}: no operation with a request body`);
  const { pointer } = follow(openapi, `${operation.pointer}/requestBody`);
  return ajv.getSchema(`openapi.yaml${pointer}/content/application~1json/schema`)(json);
}

/** A JSON error that is not an OpenAPI operation's (a refused WebSocket upgrade). */
function checkPlainError(what, reply) {
  assert.equal(mediaTypeOf(reply.headers), 'application/json', `${what}: content type`);
  checkSchema('openapi.yaml', '#/components/schemas/Error', JSON.parse(reply.body), what);
}

// --- WebSocket (AsyncAPI) ---

/**
 * A message of asyncapi.yaml: a JSON one by the `type` its payload carries, or a binary one (content
 * type application/octet-stream), with where its payload schema is.
 */
function messageAt(ref) {
  const { node, pointer } = follow(asyncapi, ref);
  const binary = (node.contentType ?? asyncapi.defaultContentType) === 'application/octet-stream';
  assert.ok(binary || node.payload?.properties?.type?.const, `${pointer}: a JSON message's payload names its type as properties.type.const`);
  return { name: pointer.split('/').pop(), binary, type: binary ? undefined : node.payload.properties.type.const, payloadPointer: `${pointer}/payload` };
}

const operationsWith = (action) => Object.entries(asyncapi.operations).filter(([, operation]) => operation.action === action);

// What the client sends (the server receives), each with the answers it may get.
const socketOperations = operationsWith('receive').map(([name, operation]) => ({
  key: `WS ${name}`,
  request: messageAt(operation.messages[0].$ref),
  replies: operation.reply.messages.map((message) => messageAt(message.$ref)),
}));

// What the server sends unasked (state frames; camera frames after them, binary).
const socketPushes = operationsWith('send').flatMap(([name, operation]) =>
  operation.messages.map((message) => ({ key: `WS ${name}`, message: messageAt(message.$ref) })));

// What a message of no known type gets: "a wrong message gets an error answer".
const errorReply = messageAt('#/components/messages/error');

/**
 * Checks the answer to a sent message: it must be one of the answers the message's operation lists,
 * a JSON one picked by its `type` and matching that payload schema, or the binary one when the
 * operation has one (its bytes are the test's to decode). A message the server answered without an
 * error must itself match the spec. Returns the asyncapi message the answer is.
 */
function checkSocketReply(sent, reply, { binary = false } = {}) {
  const operation = socketOperations.find((candidate) => candidate.request.type === sent?.type);
  const allowed = operation ? operation.replies : [errorReply];
  const names = allowed.map((m) => (m.binary ? `${m.name} (binary)` : m.type)).join(', ');
  const expected = binary ? allowed.find((message) => message.binary) : allowed.find((message) => !message.binary && message.type === reply.type);
  assert.ok(expected, `a '${sent?.type}' message got ${binary ? 'a binary' : `a '${reply.type}'`} answer; the spec allows ${names}`);
  if (!binary) checkSchema('asyncapi.yaml', expected.payloadPointer, reply, `the reply to ${JSON.stringify(sent)}`);
  if (operation && (binary || reply.type !== 'error')) {
    checkSchema('asyncapi.yaml', operation.request.payloadPointer, sent, 'a message the server accepted');
    covered.add(operation.key);
  }
  return expected;
}

/** True for a JSON message the server sends unasked (a state frame): one of the JSON pushes the spec lists. */
const isPushed = (message) => socketPushes.some((push) => !push.message.binary && push.message.type === message?.type);

/**
 * Checks a pushed message against its payload schema; a binary one (a Buffer) must be a push the spec
 * lists as binary (its bytes are the test's to decode).
 */
function checkSocketPush(message, { binary = false } = {}) {
  if (binary) {
    const push = socketPushes.find((candidate) => candidate.message.binary);
    assert.ok(push, 'the server pushed a binary message; the spec pushes none');
    covered.add(push.key);
    return;
  }
  const push = socketPushes.find((candidate) => !candidate.message.binary && candidate.message.type === message.type);
  assert.ok(push, `the server pushed a '${message.type}' message; the spec pushes ${socketPushes.filter((p) => !p.message.binary).map((p) => p.message.type)}`);
  checkSchema('asyncapi.yaml', push.message.payloadPointer, message, `a pushed '${message.type}' message`);
  covered.add(push.key);
}

/**
 * What is wrong with the documents themselves: a key without a value (in YAML, `{description: a, b}`
 * is a description "a" and a key "b") and a schema Ajv's strict mode refuses (a misspelt keyword),
 * wherever it is, reached by a test or not.
 */
function specProblems() {
  const problems = [];
  const walk = (documentId, node, pointer) => {
    for (const [key, value] of Object.entries(node)) {
      const at = `${pointer}/${escapePointer(key)}`;
      if (value === null && !Array.isArray(node) && !['default', 'example', 'const'].includes(key)) problems.push(`${documentId}${at}: a key without a value`);
      const isSchema = ['schema', 'payload'].includes(key) || pointer === '#/components/schemas' ||
        (pointer.endsWith('/bindings/ws') && ['query', 'headers'].includes(key));
      if (isSchema && value && typeof value === 'object') {
        try {
          ajv.getSchema(documentId + at);
        } catch (error) {
          problems.push(`${documentId}${at}: ${error.message}`);
        }
      }
      if (value && typeof value === 'object') walk(documentId, value, at);
    }
  };
  walk('openapi.yaml', openapi, '#');
  walk('asyncapi.yaml', asyncapi, '#');
  return problems;
}

/** Operations of either spec that no test has seen succeed. */
function unexercisedOperations() {
  return [...new Set([...httpOperations, ...socketOperations, ...socketPushes].map((operation) => operation.key))].filter((key) => !covered.has(key));
}

module.exports = {
  repoRoot, openapi, asyncapi, httpOperations, checkHttpExchange, checkPlainError, checkSocketReply, isPushed,
  checkSocketPush, specAllows, specProblems, unexercisedOperations,
};
