// A stored episode filmed by the server as a video (POST /api/v1/episodes/{id}/videos): a small form
// (one of the episode's cameras, MP4 or WebM, frames per second, a width), the job's progress while it
// films (its status polled), a button that cancels it, then the video playing in the page with a
// download link. The server judges the form: its message for a field shows beside the form, and that
// field is marked. The episode page shows it under its header line; destroy() stops the polling when
// the page is left (the job goes on on the server: asking again with the same options finds it).
import { api, authorisedUrl } from '../lib/api.js';
import { h, showError, formatNumber } from '../lib/ui.js';
import { downloadLink } from '../lib/download.js';

const POLL_MS = 400;
const FORMATS = [{ value: 'mp4', text: 'MP4 (H.264)' }, { value: 'webm', text: 'WebM (VP8)' }];
const CODECS = { h264: 'H.264', vp8: 'VP8' };
const DEFAULT_CAMERA = 'overview';
const DEFAULT_FPS = 25;

/** A file's size in kB or MB (powers of 1000, as file managers show them). */
function fileSize(bytes) {
  if (bytes < 1000) return `${bytes} B`;
  return bytes < 1e6 ? `${formatNumber(bytes / 1e3, 2)} kB` : `${formatNumber(bytes / 1e6, 2)} MB`;
}

/** What a job's status reads as while it waits or films. */
function progressText(job) {
  if (job.status === 'queued') return 'Queued… the server starts filming soon.';
  const { tick, ticks, fraction } = job.progress;
  return `Filming… ${Math.floor(fraction * 100)} % (tick ${tick.toLocaleString('en')} of ${ticks.toLocaleString('en')})`;
}

/**
 * The toggle button (for the page's header line) and the panel it opens, for episode `id`. The
 * cameras are asked for when the panel first opens.
 */
export function videoExport(id) {
  const episodePath = `/api/v1/episodes/${encodeURIComponent(id)}`;
  const camera = h('select', { id: 'video-camera', name: 'camera', disabled: true });
  const format = h('select', { id: 'video-format', name: 'format' }, FORMATS.map((f) => h('option', { value: f.value }, f.text)));
  const fps = h('input', { id: 'video-fps', name: 'fps', type: 'number', min: 1, max: 120, step: 1, value: DEFAULT_FPS, size: 4 });
  // Empty: the camera's own width (its placeholder); the height follows the camera's proportions.
  const width = h('input', { id: 'video-width', name: 'width', type: 'number', min: 16, max: 1920, step: 1, size: 6 });
  const fields = { '/camera': camera, '/format': format, '/fps': fps, '/width': width, '/height': width };
  const submit = h('button', { type: 'submit', disabled: true }, 'Film the episode');
  const errors = h('div', { id: 'video-error', class: 'video-error' });
  const form = h('form', { class: 'video-form', novalidate: true, onsubmit: (event) => { event.preventDefault(); start(); } },
    h('div', { class: 'fields' },
      h('label', { for: 'video-camera' }, 'Camera', camera),
      h('label', { for: 'video-format' }, 'Format', format),
      h('label', { for: 'video-fps' }, 'Frames per second', fps),
      h('label', { for: 'video-width' }, 'Width (px, optional)', width),
      submit));
  // The job: its progress and status (announced), Cancel, then the video and its file.
  const progress = h('progress', { id: 'video-progress', max: 1, 'aria-label': 'Filming progress' });
  const status = h('p', { id: 'video-status', class: 'video-status', role: 'status', 'aria-live': 'polite' });
  const cancel = h('button', { type: 'button', class: 'secondary danger', onclick: () => cancelJob() }, 'Cancel');
  const running = h('div', { class: 'video-running', hidden: true }, progress, cancel);
  const result = h('div', { class: 'video-result' });
  const panel = h('section', { id: 'video-export', class: 'panel video-export', 'aria-labelledby': 'video-title', hidden: true },
    h('h2', { id: 'video-title' }, 'Export video'),
    h('p', { class: 'muted small' }, 'The server replays the episode and films it from one of its cameras.'),
    form, errors, running, status, result);
  const toggle = h('button', { type: 'button', class: 'secondary', 'aria-expanded': 'false', 'aria-controls': 'video-export',
    onclick: () => {
      panel.hidden = !panel.hidden;
      toggle.setAttribute('aria-expanded', String(!panel.hidden));
      if (!panel.hidden && !camerasAsked) loadCameras();
    } }, 'Export video');

  let camerasAsked = false;
  let cameras = [];
  let job = null;
  let timer = null;
  // A new job, a cancel or leaving the page makes older answers stale.
  let generation = 0;
  let objectUrl = null;

  async function loadCameras() {
    camerasAsked = true;
    camera.append(h('option', { value: '' }, 'Loading the cameras…'));
    try {
      cameras = (await api.get(`${episodePath}/cameras`)).cameras;
    } catch (error) {
      camera.replaceChildren(h('option', { value: '' }, 'No camera'));
      camerasAsked = false;  // asked again when the panel opens again
      showProblem(new Error(`The episode's cameras could not be loaded: ${error.message}`));
      return;
    }
    camera.replaceChildren(...cameras.map((c) => h('option', { value: c.name, selected: c.name === DEFAULT_CAMERA },
      `${c.name} (${c.kind}, ${c.width}×${c.height})`)));
    camera.disabled = false;
    submit.disabled = false;
    showCameraSize();
  }
  const showCameraSize = () => {
    const chosen = cameras.find((c) => c.name === camera.value);
    width.placeholder = chosen ? String(chosen.width) : '';
  };
  camera.addEventListener('change', showCameraSize);

  function clearProblems() {
    errors.replaceChildren();
    for (const field of Object.values(fields)) field.removeAttribute('aria-invalid');
  }
  /** The server's message beside the form; the field its pointer names is marked. */
  function showProblem(error) {
    errors.replaceChildren();
    showError(errors, error);
    const field = fields[error.details?.pointer];
    if (field) {
      field.setAttribute('aria-invalid', 'true');
      field.focus();
    }
  }

  const setBusy = (busy) => {
    submit.disabled = busy || !cameras.length;
    running.hidden = !busy;
  };

  function forgetVideo() {
    result.replaceChildren();
    if (objectUrl) URL.revokeObjectURL(objectUrl);
    objectUrl = null;
  }

  /** The form as the request's body: empty fields are left to the server's defaults. */
  function body() {
    const options = { camera: camera.value, format: format.value };
    if (fps.value.trim() !== '') options.fps = Number(fps.value);
    if (width.value.trim() !== '') options.width = Number(width.value);
    return options;
  }

  async function start() {
    const current = ++generation;
    clearTimeout(timer);
    clearProblems();
    forgetVideo();
    status.textContent = '';
    // What the browser cannot read as a number (its value is '' then) never reaches the server: said here.
    const unreadable = [['/fps', 'frames per second'], ['/width', 'the width']].find(([pointer]) => fields[pointer].validity.badInput);
    if (unreadable) {
      showProblem(Object.assign(new Error(`${unreadable[1]} must be a number`), { details: { pointer: unreadable[0] } }));
      return;
    }
    const options = body();
    submit.disabled = true;
    try {
      job = await api.post(`${episodePath}/videos`, options);
    } catch (error) {
      if (current !== generation) return;
      setBusy(false);
      showProblem(error);
      return;
    }
    if (current !== generation) return;
    show(job, current);
  }

  async function poll(current) {
    let next;
    try {
      next = await api.get(`/api/v1/videos/${encodeURIComponent(job.id)}`);
    } catch (error) {
      if (current !== generation) return;
      setBusy(false);
      status.textContent = '';
      showProblem(new Error(`The video's status could not be read: ${error.message}`));
      return;
    }
    if (current !== generation) return;
    job = next;
    show(job, current);
  }

  function show(state, current) {
    if (state.status === 'queued' || state.status === 'filming') {
      setBusy(true);
      if (state.status === 'queued') progress.removeAttribute('value');
      else progress.value = state.progress.fraction;
      status.textContent = progressText(state);
      timer = setTimeout(() => poll(current), POLL_MS);
      return;
    }
    setBusy(false);
    if (state.status === 'done') {
      status.textContent = `Filmed in ${formatNumber(state.elapsed, 2)} s.`;
      showVideo(state, current);
    } else if (state.status === 'failed') {
      status.textContent = '';
      showProblem(new Error(`Filming failed: ${state.error ?? 'the server gave no reason'}`));
    } else {
      status.textContent = 'The filming was cancelled.';
    }
  }

  async function showVideo(state, current) {
    let source;
    try {
      source = await authorisedUrl(state.file);
    } catch (error) {
      if (current === generation) showProblem(new Error(`The video could not be loaded: ${error.message}`));
      return;
    }
    if (current !== generation) {
      if (source !== state.file) URL.revokeObjectURL(source);
      return;
    }
    if (source !== state.file) objectUrl = source;
    const codec = CODECS[state.codec] ?? state.codec;
    const video = h('video', { class: 'episode-video', controls: true, preload: 'metadata', src: source, width: state.width, height: state.height,
      'aria-label': `Episode ${id.slice(0, 9)} filmed by the ${state.camera} camera, ${formatNumber(state.frames / state.video_fps, 2)} s` });
    const unplayable = h('p', { class: 'message error', role: 'alert', hidden: true },
      `This browser cannot play ${codec} video: download the file to watch it.`);
    video.addEventListener('error', () => { unplayable.hidden = false; });
    result.replaceChildren(...[
      video, unplayable,
      h('p', { class: 'video-file' },
        downloadLink(state.file, `${id}-${state.camera}.${state.format}`, `Download the video (${fileSize(state.bytes)})`, { class: 'button secondary video-download' }),
        h('span', { class: 'muted small' }, ` ${state.format.toUpperCase()}, ${codec}, ${state.width}×${state.height}, `
          + `${state.frames.toLocaleString('en')} frames at ${formatNumber(state.video_fps)} fps`)),
      state.matches_stored_episode === false
        ? h('p', { class: 'message warn video-mismatch' }, 'The replay the server filmed did not end in the stored episode\'s final state: '
          + 'the video may not show exactly what was recorded (the scenario or the simulator changed since).')
        : null,
    ].filter(Boolean));
  }

  async function cancelJob() {
    if (!job) return;
    const current = ++generation;
    clearTimeout(timer);
    cancel.disabled = true;
    try {
      await api.delete(`/api/v1/videos/${encodeURIComponent(job.id)}`);
      if (current !== generation) return;
      status.textContent = 'Cancelled: the server stopped filming.';
    } catch (error) {
      if (current !== generation) return;
      showProblem(new Error(`The filming could not be cancelled: ${error.message}`));
    } finally {
      cancel.disabled = false;
      if (current === generation) {
        job = null;
        setBusy(false);
      }
    }
  }

  return {
    toggle,
    panel,
    destroy() {
      generation++;
      clearTimeout(timer);
      forgetVideo();
    },
  };
}
