// The camera panel: a choice of the session's cameras and the last frame the driver fetched of it.
import { h } from '../lib/ui.js';
import { CAMERA_SIZE } from './driver.js';
import { errorText, showMessage } from './messages.js';

/** The fixed header of a camera frame (HRCF) before its RGBA pixels. */
const HRCF_HEADER_BYTES = 96;

/** The panel for `cameras` (GET …/cameras): first a camera that sees like one, else the follow view. */
export function cameraPanel(driver, cameras) {
  const first = (cameras.find((c) => c.kind === 'camera' || c.kind === 'rgbd_camera')
    ?? cameras.find((c) => c.name === 'follow') ?? cameras[0])?.name ?? null;
  const select = h('select', { onchange: () => driver.setCamera(select.value) },
    cameras.map((c) => h('option', { value: c.name, selected: c.name === first }, `${c.name} (${c.kind})`)));
  const canvas = h('canvas', { class: 'camera-frame', width: CAMERA_SIZE.width, height: CAMERA_SIZE.height, role: 'img', 'aria-label': 'Camera frame' });
  const caption = h('p', { class: 'muted camera-caption' }, 'Waiting for the first frame…');
  const error = h('p', { class: 'message error', role: 'alert', hidden: true });

  driver.setCamera(first);
  driver.on('frame', (buffer) => {
    const view = new DataView(buffer);
    const width = view.getUint32(24, true);
    const height = view.getUint32(28, true);
    const tick = Number(view.getBigInt64(8, true));
    const name = new TextDecoder().decode(new Uint8Array(buffer, 60, 36)).replace(/\0.*$/s, '');
    if (canvas.width !== width || canvas.height !== height) Object.assign(canvas, { width, height });
    const pixels = new Uint8ClampedArray(buffer, HRCF_HEADER_BYTES, width * height * 4);
    canvas.getContext('2d').putImageData(new ImageData(pixels, width, height), 0, 0);
    canvas.dataset.tick = String(tick);
    canvas.setAttribute('aria-label', `Frame of camera ${name} at tick ${tick}`);
    caption.textContent = `${name} · tick ${tick} · ${width} × ${height} px`;
    error.hidden = true;
  });
  driver.on('cameraError', (reason) => showMessage(error, 'error', `No frame from ${select.value}: ${errorText(reason)}`));

  return h('section', { class: 'panel camera-panel', 'aria-label': 'Camera' },
    h('h2', {}, 'Camera'), h('label', {}, 'Camera', select), canvas, caption, error);
}
