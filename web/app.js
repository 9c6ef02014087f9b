// Placeholder page logic: shows the server's health and version from the REST API.
async function fetchJson(path) {
  const response = await fetch(path);
  const body = await response.json();
  if (!response.ok) throw new Error(body.error ? body.error.message : response.statusText);
  return body;
}

function show(id, text, cls) {
  const element = document.getElementById(id);
  element.textContent = text;
  if (cls) element.className = cls;
}

fetchJson('/healthz')
  .then((health) => show('health', `${health.status} (database ${health.database})`, 'ok'))
  .catch((error) => show('health', error.message, 'error'));

fetchJson('/api/v1/version')
  .then((version) => {
    show('version', `${version.version} (${version.build_type}, ${version.compiler})`);
    show('commit', version.git_commit);
  })
  .catch((error) => show('version', error.message, 'error'));
