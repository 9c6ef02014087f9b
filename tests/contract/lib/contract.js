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

// Both documents are added whole, so a schema is named by its JSON pointer (openapi.json#/components/...)
// and its own "#/components/..." references resolve inside its document. Ajv understands OpenAPI 3.0's
// `nullable` itself; `example` and the documents' top-level keys (paths, channels, ...) are no schema
// keywords, so they are declared as annotations and strict mode still catches misspelt keywords.
const ajv = new Ajv2020({ strict: true, allErrors: true });
addFormats(ajv);
for (const keyword of new Set(['example', ...Object.keys(openapi), ...Object.keys(asyncapi)])) {
  if (!ajv.getKeyword(keyword)) ajv.addKeyword(keyword);
}
ajv.addSchema(openapi, 'openapi.json');
ajv.addSchema(asyncapi, 'asyncapi.json');

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
    checkSchema('openapi.json', '#/components/schemas/Error', JSON.parse(reply.body), what);
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
      checkSchema('openapi.json', `${pointer}/content/application~1json/schema`, JSON.parse(reply.body), what);
    }
  }
  if (reply.status < 300 && request.json !== undefined && operation.operation.requestBody) {
    const { pointer: body } = follow(openapi, `${operation.pointer}/requestBody`);
    checkSchema('openapi.json', `${body}/content/application~1json/schema`, request.json, `${what}: the request the server accepted`);
  }
  if (reply.status < 300) covered.add(operation.key);
  return operation;
}

/** A JSON error that is not an OpenAPI operation's (a refused WebSocket upgrade). */
function checkPlainError(what, reply) {
  assert.equal(mediaTypeOf(reply.headers), 'application/json', `${what}: content type`);
  checkSchema('openapi.json', '#/components/schemas/Error', JSON.parse(reply.body), what);
}

// --- WebSocket (AsyncAPI) ---

/** A message's payload schema and the `type` it carries. */
function messageAt(ref) {
  const { node, pointer } = follow(asyncapi, ref);
  return { type: node.payload.properties.type.const, payloadPointer: `${pointer}/payload` };
}

const socketOperations = Object.entries(asyncapi.operations).map(([name, operation]) => ({
  key: `WS ${name}`,
  request: messageAt(operation.messages[0].$ref),
  replies: operation.reply.messages.map((message) => messageAt(message.$ref)),
}));

// What a message of no known type gets: "a wrong message gets an error answer".
const errorReply = messageAt('#/components/messages/error');

/**
 * Checks the reply to a sent message: it must be one of the replies the message's operation lists,
 * picked by its `type`, and match that payload schema. A message the server answered without an
 * error must itself match the spec.
 */
function checkSocketReply(sent, reply) {
  const operation = socketOperations.find((candidate) => candidate.request.type === sent?.type);
  const allowed = operation ? operation.replies : [errorReply];
  const expected = allowed.find((message) => message.type === reply.type);
  assert.ok(expected, `a '${sent?.type}' message got a '${reply.type}' reply; the spec allows ${allowed.map((m) => m.type).join(', ')}`);
  checkSchema('asyncapi.json', expected.payloadPointer, reply, `the reply to ${JSON.stringify(sent)}`);
  if (operation && reply.type !== 'error') {
    checkSchema('asyncapi.json', operation.request.payloadPointer, sent, 'a message the server accepted');
    covered.add(operation.key);
  }
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
      const isSchema = ['schema', 'payload'].includes(key) || pointer === '#/components/schemas';
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
  walk('openapi.json', openapi, '#');
  walk('asyncapi.json', asyncapi, '#');
  return problems;
}

/** Operations of either spec that no test has seen succeed. */
function unexercisedOperations() {
  return [...httpOperations, ...socketOperations].map((operation) => operation.key).filter((key) => !covered.has(key));
}

module.exports = {
  repoRoot, openapi, asyncapi, httpOperations, checkHttpExchange, checkPlainError, checkSocketReply,
  specProblems, unexercisedOperations,
};
