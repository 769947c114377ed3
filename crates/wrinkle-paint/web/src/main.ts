/**
 * The page of `wrinkle paint` (docs/paint.md, "The page"): the view the server renders, streamed over the
 * WebSocket /api/ws, painted with the left button, orbited, panned and zoomed; the brush toolbar; the atlas of
 * the current channel; undo, redo and save.
 */
import './style.css';
import { channelName, getJson, postJson, type PaintState } from './api';
import * as cam from './camera';
import { hexToLinear } from './color';
import { Link } from './link';

/** What a test can wait on: `window.wrinklePaint`. */
interface Probe {
  framesReceived: number;
  lastLatencyMs: number;
  lastStrokeTexels: number;
  connected: boolean;
}

declare global {
  interface Window {
    wrinklePaint: Probe;
  }
}

const probe: Probe = { framesReceived: 0, lastLatencyMs: 0, lastStrokeTexels: 0, connected: false };
window.wrinklePaint = probe;

function byId<T extends HTMLElement>(id: string): T {
  const e = document.getElementById(id);
  if (!e) throw new Error(`the page lacks #${id}`);
  return e as T;
}

const canvas = byId<HTMLCanvasElement>('view');
const ctx = canvas.getContext('2d')!;
const channelSelect = byId<HTMLSelectElement>('channel');
const colorInput = byId<HTMLInputElement>('color');
const valueInput = byId<HTMLInputElement>('value');
const radiusInput = byId<HTMLInputElement>('radius');
const radiusObjectInput = byId<HTMLInputElement>('radius-object');
const objectSpaceInput = byId<HTMLInputElement>('object-space');
const hardnessInput = byId<HTMLInputElement>('hardness');
const opacityInput = byId<HTMLInputElement>('opacity');
const spacingInput = byId<HTMLInputElement>('spacing');
const eraserInput = byId<HTMLInputElement>('eraser');
const mirrorInput = byId<HTMLInputElement>('mirror');
const undoButton = byId<HTMLButtonElement>('undo');
const redoButton = byId<HTMLButtonElement>('redo');
const saveButton = byId<HTMLButtonElement>('save');
const statusLine = byId<HTMLElement>('status');
const atlasImage = byId<HTMLImageElement>('atlas');
const atlasCaption = byId<HTMLElement>('atlas-channel');

const DEFAULT_CHANNELS = ['color', 'height', 'specular', 'opacity'];
/** The renderer's default vertical field of view, when the state names none. */
const DEFAULT_FOV_Y = 40;

let camera: cam.Camera = { yaw: 0, pitch: 0, distance: 4, target: [0, 0, 0] };
let fovY = DEFAULT_FOV_Y;
let minDistance = 1e-3;
let maxDistance = 1e4;
let zoomRangeSet = false;
let channel = 'color';
/** The value slider remembered per scalar channel. */
const channelValues = new Map<string, number>();

// ---------------------------------------------------------------------------------------------- status

let message = '';
let messageIsError = false;
/** The undo and redo steps available, as the server last said (state and stroke messages). */
let steps: { undo: number; redo: number } | null = null;

function setHistory(undo: unknown, redo: unknown): void {
  if (typeof undo === 'number' && typeof redo === 'number') steps = { undo, redo };
}

function setMessage(text: string, isError = false): void {
  message = text;
  messageIsError = isError;
  renderStatus();
}

function renderStatus(): void {
  const parts = [
    probe.connected ? 'connected' : 'disconnected',
    `last stroke: ${probe.lastStrokeTexels} texels`,
    `frame latency: ${probe.lastLatencyMs.toFixed(1)} ms`,
  ];
  if (steps) parts.push(`undo ${steps.undo} · redo ${steps.redo}`);
  if (message) parts.push(message);
  statusLine.textContent = parts.join(' · ');
  statusLine.classList.toggle('error', messageIsError);
}

// ---------------------------------------------------------------------------------------------- frames

let framesDecoded = 0;
let newestDrawn = 0;

async function showFrame(blob: Blob, latencyMs: number | null): Promise<void> {
  const seq = ++framesDecoded;
  if (latencyMs !== null) probe.lastLatencyMs = Math.round(latencyMs * 10) / 10;
  let bitmap: ImageBitmap;
  try {
    bitmap = await createImageBitmap(blob);
  } catch {
    setMessage(`a frame (${blob.type}) could not be decoded`, true);
    return;
  }
  // Decoding is asynchronous: a frame finished after a newer one is not drawn over it.
  if (seq > newestDrawn) {
    newestDrawn = seq;
    ctx.drawImage(bitmap, 0, 0, canvas.width, canvas.height);
  }
  bitmap.close();
  probe.framesReceived += 1;
  renderStatus();
}

// ---------------------------------------------------------------------------------------------- state

function applyState(s: PaintState, takeCamera: boolean): void {
  setHistory(s.undo, s.redo);
  if (Number.isFinite(s.width) && Number.isFinite(s.height) && s.width > 0 && s.height > 0) {
    if (canvas.width !== s.width || canvas.height !== s.height) {
      canvas.width = s.width;
      canvas.height = s.height;
      newestDrawn = framesDecoded; // the resize cleared the canvas; the next frame draws
    }
  }
  const names = (Array.isArray(s.channels) ? s.channels.map(channelName) : []).filter((n): n is string => !!n);
  fillChannels(names.length > 0 ? names : DEFAULT_CHANNELS);
  if (s.camera) {
    const c = s.camera;
    const f = c.fov_y ?? c.fov ?? (s.fov_y as number | undefined) ?? (s.fov as number | undefined);
    if (typeof f === 'number' && f > 0 && f < 180) fovY = f;
    if (takeCamera && !drag) {
      const t = Array.isArray(c.target) && c.target.length === 3 ? c.target : [0, 0, 0];
      camera = { yaw: c.yaw, pitch: c.pitch, distance: c.distance, target: [t[0], t[1], t[2]] };
      if (!zoomRangeSet && c.distance > 0) {
        // The wheel zooms between 1/50 and 50 times the distance the model was first seen from.
        minDistance = c.distance / 50;
        maxDistance = c.distance * 50;
        zoomRangeSet = true;
      }
    }
  }
}

function fillChannels(names: string[]): void {
  const current = Array.from(channelSelect.options).map((o) => o.value);
  if (current.join('\n') !== names.join('\n')) {
    channelSelect.replaceChildren(
      ...names.map((n) => {
        const o = document.createElement('option');
        o.value = n;
        o.textContent = n;
        return o;
      }),
    );
  }
  if (!names.includes(channel)) channel = names[0];
  channelSelect.value = channel;
  showChannelFields();
}

async function loadState(): Promise<void> {
  for (;;) {
    try {
      applyState(await getJson<PaintState>('/api/state'), true);
      if (messageIsError && message.startsWith('GET /api/state')) setMessage('');
      return;
    } catch (e) {
      setMessage(`GET /api/state: ${(e as Error).message}`, true);
      await new Promise((r) => setTimeout(r, 1000));
    }
  }
}

// ---------------------------------------------------------------------------------------------- atlas

let atlasCounter = 0;
/** Makes the atlas addresses of this page load its own, so that no cached image from an earlier one shows. */
const atlasSession = Date.now().toString(36);

function refreshAtlas(): void {
  atlasCounter += 1;
  atlasCaption.textContent = channel;
  atlasImage.src = `/api/atlas/${encodeURIComponent(channel)}.png?t=${atlasSession}-${atlasCounter}`;
}

// ---------------------------------------------------------------------------------------------- the link

const wsUrl = `${location.protocol === 'https:' ? 'wss:' : 'ws:'}//${location.host}/api/ws`;
let everOpened = false;

const link = new Link(wsUrl, {
  open() {
    probe.connected = true;
    if (everOpened) {
      // Reconnected: the server may have changed meanwhile.
      loadState().then(() => refreshAtlas());
    }
    everOpened = true;
    link.send({ type: 'frame', lossless: true });
    renderStatus();
  },
  close() {
    probe.connected = false;
    if (drag && drag.mode === 'paint') drag = null; // the server ended the stroke with the connection
    renderStatus();
  },
  frame(blob, latencyMs) {
    void showFrame(blob, latencyMs);
  },
  message(msg) {
    switch (msg.type) {
      case 'stroke':
        probe.lastStrokeTexels = Number(msg.texels) || 0;
        setHistory(msg.undo, msg.redo);
        refreshAtlas();
        renderStatus();
        break;
      case 'state':
        applyState(msg as unknown as PaintState, true);
        renderStatus();
        break;
      case 'error':
        setMessage(`error: ${String(msg.message ?? 'unknown')}`, true);
        break;
      default:
        break;
    }
  },
});

// ---------------------------------------------------------------------------------------------- brush

function brush(): Record<string, unknown> {
  const objectSpace = objectSpaceInput.checked;
  const b: Record<string, unknown> = {
    channel,
    radius: Number(objectSpace ? radiusObjectInput.value : radiusInput.value),
    space: objectSpace ? 'object' : 'screen',
    hardness: Number(hardnessInput.value),
    opacity: Number(opacityInput.value),
    spacing: Number(spacingInput.value),
    erase: eraserInput.checked,
    mirror_x: mirrorInput.checked,
  };
  if (channel === 'color') b.color = hexToLinear(colorInput.value);
  else b.value = Number(valueInput.value);
  return b;
}

function showChannelFields(): void {
  const isColor = channel === 'color';
  byId('color-field').hidden = !isColor;
  byId('value-field').hidden = isColor;
  if (!isColor) {
    valueInput.value = String(channelValues.get(channel) ?? 1);
    showOutputs();
  }
}

function showOutputs(): void {
  byId('value-out').textContent = Number(valueInput.value).toFixed(2);
  byId('radius-out').textContent = `${radiusInput.value} px`;
  byId('hardness-out').textContent = Number(hardnessInput.value).toFixed(2);
  byId('opacity-out').textContent = Number(opacityInput.value).toFixed(2);
  byId('spacing-out').textContent = Number(spacingInput.value).toFixed(2);
  byId('radius-field').hidden = objectSpaceInput.checked;
  byId('radius-object-field').hidden = !objectSpaceInput.checked;
}

channelSelect.addEventListener('change', () => {
  channel = channelSelect.value;
  showChannelFields();
  refreshAtlas();
});
valueInput.addEventListener('input', () => {
  channelValues.set(channel, Number(valueInput.value));
  showOutputs();
});
for (const input of [radiusInput, hardnessInput, opacityInput, spacingInput, objectSpaceInput]) {
  input.addEventListener('input', showOutputs);
  input.addEventListener('change', showOutputs);
}

// ---------------------------------------------------------------------------------------------- mouse

type Drag = { mode: 'paint' | 'orbit' | 'pan'; button: number; x: number; y: number };
let drag: Drag | null = null;

/** The mouse in pixels of the view (the canvas may be shown at another size), row 0 at the top. */
function viewPoint(ev: MouseEvent): [number, number] {
  const r = canvas.getBoundingClientRect();
  const x = ((ev.clientX - r.left) * canvas.width) / Math.max(1, r.width);
  const y = ((ev.clientY - r.top) * canvas.height) / Math.max(1, r.height);
  return [Math.round(x * 100) / 100, Math.round(y * 100) / 100];
}

function sendCamera(): void {
  link.send({ type: 'camera', yaw: camera.yaw, pitch: camera.pitch, distance: camera.distance, target: camera.target });
}

function endStroke(): void {
  if (drag && drag.mode === 'paint') {
    link.send({ type: 'stroke_end' });
  }
  drag = null;
}

canvas.addEventListener('contextmenu', (ev) => ev.preventDefault());

canvas.addEventListener('mousedown', (ev) => {
  if (drag) return;
  let mode: Drag['mode'];
  if (ev.button === 1 || (ev.shiftKey && (ev.button === 0 || ev.button === 2))) mode = 'pan';
  else if (ev.button === 2 || (ev.button === 0 && ev.altKey)) mode = 'orbit';
  else if (ev.button === 0) mode = 'paint';
  else return;
  ev.preventDefault();
  const [x, y] = viewPoint(ev);
  drag = { mode, button: ev.button, x, y };
  if (mode === 'paint') {
    link.send({ type: 'stroke_begin', ...brush() });
    link.send({ type: 'stroke_point', x, y });
  }
});

window.addEventListener('mousemove', (ev) => {
  if (!drag) return;
  const [x, y] = viewPoint(ev);
  const dx = x - drag.x;
  const dy = y - drag.y;
  if (dx === 0 && dy === 0) return;
  drag.x = x;
  drag.y = y;
  switch (drag.mode) {
    case 'paint':
      if ((ev.buttons & 1) === 0) {
        endStroke(); // released where the page did not see it
        return;
      }
      link.send({ type: 'stroke_point', x, y });
      break;
    case 'orbit':
      camera = cam.orbit(camera, dx, dy);
      sendCamera();
      break;
    case 'pan':
      camera = cam.pan(camera, dx, dy, canvas.height, fovY);
      sendCamera();
      break;
  }
});

window.addEventListener('mouseup', (ev) => {
  if (!drag || ev.button !== drag.button) return;
  if (drag.mode === 'paint') {
    endStroke();
  } else {
    drag = null;
    link.send({ type: 'frame', lossless: true });
  }
});

canvas.addEventListener('mouseleave', () => {
  if (drag && drag.mode === 'paint') endStroke();
});

let wheelTimer: number | undefined;
canvas.addEventListener(
  'wheel',
  (ev) => {
    ev.preventDefault();
    const notches = ev.deltaMode === WheelEvent.DOM_DELTA_PIXEL ? ev.deltaY / 100
      : ev.deltaMode === WheelEvent.DOM_DELTA_LINE ? ev.deltaY / 3
      : ev.deltaY;
    if (notches === 0) return;
    camera = cam.zoom(camera, notches, minDistance, maxDistance);
    sendCamera();
    window.clearTimeout(wheelTimer);
    wheelTimer = window.setTimeout(() => link.send({ type: 'frame', lossless: true }), 250);
  },
  { passive: false },
);

// ---------------------------------------------------------------------------------------------- undo, redo, save

async function undoRedo(kind: 'undo' | 'redo'): Promise<void> {
  if (drag && drag.mode === 'paint') endStroke();
  if (link.connected) {
    link.send({ type: kind });
    return;
  }
  try {
    const r = await postJson<{ texels: number; undo?: number; redo?: number }>(`/api/${kind}`, {});
    probe.lastStrokeTexels = Number(r.texels) || 0;
    setHistory(r.undo, r.redo);
    refreshAtlas();
    renderStatus();
  } catch (e) {
    setMessage(`${kind}: ${(e as Error).message}`, true);
  }
}

undoButton.addEventListener('click', () => void undoRedo('undo'));
redoButton.addEventListener('click', () => void undoRedo('redo'));

saveButton.addEventListener('click', async () => {
  saveButton.disabled = true;
  setMessage('saving…');
  try {
    const r = await postJson<{ scene: string; files?: string[] }>('/api/save', {});
    setMessage(`saved: ${r.scene}`);
  } catch (e) {
    setMessage(`save: ${(e as Error).message}`, true);
  } finally {
    saveButton.disabled = false;
  }
});

window.addEventListener('keydown', (ev) => {
  if (!(ev.ctrlKey || ev.metaKey) || ev.altKey) return;
  const t = ev.target as HTMLElement | null;
  if (t instanceof HTMLInputElement && (t.type === 'text' || t.type === 'number')) return;
  const key = ev.key.toLowerCase();
  if (key === 'z') {
    ev.preventDefault();
    void undoRedo(ev.shiftKey ? 'redo' : 'undo');
  } else if (key === 'y') {
    ev.preventDefault();
    void undoRedo('redo');
  }
});

// ---------------------------------------------------------------------------------------------- start

showOutputs();
renderStatus();
void loadState().then(() => {
  refreshAtlas();
  link.connect();
});
