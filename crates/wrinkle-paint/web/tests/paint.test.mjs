// End-to-end test of the `wrinkle paint` page against a running server (docs/paint.md).
//
//   WRINKLE_PAINT_URL=http://127.0.0.1:8478 node tests/paint.test.mjs
//
// The server (started by the Rust test harness) paints a unit sphere at the origin with the default transform.
// Headless Chromium (env CHROMIUM, default /usr/bin/chromium) opens the page, paints a red stroke across the
// middle row of the view with the mouse, and the test checks the colour atlas against the sphere's analytic
// (u, v), the rendered frame, undo and redo, and measures the stroke-to-frame latency. On success it prints one
// JSON line of measurements and exits 0; on failure it prints the error and exits 1.
import { chromium } from 'playwright-core';
import { PNG } from 'pngjs';

const BASE = (process.env.WRINKLE_PAINT_URL || '').replace(/\/+$/, '');
const CHROMIUM = process.env.CHROMIUM || '/usr/bin/chromium';
/** The longest any one wait may take. */
const WAIT_MS = 20_000;
/** The whole test is abandoned after this long. */
const OVERALL_MS = 180_000;
const CHROME_ARGS = [
  '--headless=new',
  '--no-sandbox',
  '--disable-gpu',
  '--disable-quic',
  '--no-first-run',
  '--disable-background-networking',
  '--disable-component-update',
  '--disable-sync',
];

const sleep = (ms) => new Promise((r) => setTimeout(r, ms));

function check(condition, message) {
  if (!condition) throw new Error(message);
}

async function http(method, path, body) {
  const res = await fetch(BASE + path, {
    method,
    headers: body === undefined ? {} : { 'Content-Type': 'application/json' },
    body: body === undefined ? undefined : JSON.stringify(body),
  });
  const bytes = Buffer.from(await res.arrayBuffer());
  if (!res.ok) throw new Error(`${method} ${path}: HTTP ${res.status}: ${bytes.toString('utf8').slice(0, 300)}`);
  return { res, bytes };
}

async function getJson(path) {
  return JSON.parse((await http('GET', path)).bytes.toString('utf8'));
}

async function postJson(path, body) {
  return JSON.parse((await http('POST', path, body)).bytes.toString('utf8'));
}

/** A PNG from the server, decoded to 8-bit RGBA ({width, height, data}). */
async function getPng(path) {
  const { bytes } = await http('GET', path);
  check(bytes.length >= 8 && bytes[0] === 0x89 && bytes.toString('latin1', 1, 4) === 'PNG', `GET ${path} is not a PNG`);
  return PNG.sync.read(bytes);
}

function sameImage(a, b) {
  return a.width === b.width && a.height === b.height && a.data.equals(b.data);
}

/** Polls `fn` until it returns a truthy value; throws `what` after WAIT_MS. */
async function until(what, fn, intervalMs = 100) {
  const start = Date.now();
  let last;
  for (;;) {
    last = await fn();
    if (last) return last;
    if (Date.now() - start > WAIT_MS) throw new Error(`timed out after ${WAIT_MS / 1000} s waiting for ${what}`);
    await sleep(intervalMs);
  }
}

/** Waits on the page's `window.wrinklePaint` probe. */
async function waitProbe(page, what, predicate, arg) {
  try {
    await page.waitForFunction(predicate, arg, { timeout: WAIT_MS, polling: 50 });
  } catch (e) {
    const probe = await page.evaluate(() => window.wrinklePaint).catch(() => undefined);
    const status = await page.textContent('#status').catch(() => '?');
    throw new Error(`timed out waiting for ${what} (window.wrinklePaint = ${JSON.stringify(probe)}, status: ${status})`);
  }
}

const probe = (page) => page.evaluate(() => ({ ...window.wrinklePaint }));

/** Sets a toolbar input as a person would, firing input and change. */
async function setInput(page, id, value) {
  const ok = await page.evaluate(
    ([id, value]) => {
      const e = document.getElementById(id);
      if (!e) return false;
      if (e instanceof HTMLInputElement && e.type === 'checkbox') e.checked = Boolean(value);
      else e.value = String(value);
      e.dispatchEvent(new Event('input', { bubbles: true }));
      e.dispatchEvent(new Event('change', { bubbles: true }));
      return e instanceof HTMLInputElement && e.type === 'checkbox' ? e.checked === Boolean(value) : e.value === String(value);
    },
    [id, value],
  );
  check(ok, `could not set #${id} to ${value}`);
}

/** The page coordinates of a point in pixels of the view (the canvas may be shown at another size). */
async function viewToPage(page) {
  const box = await page.evaluate(() => {
    const c = document.getElementById('view');
    const r = c.getBoundingClientRect();
    return { left: r.left, top: r.top, width: r.width, height: r.height, w: c.width, h: c.height };
  });
  check(box.width > 0 && box.height > 0, '#view is not shown');
  return {
    box,
    at: (x, y) => [box.left + (x * box.width) / box.w, box.top + (y * box.height) / box.h],
  };
}

function median(xs) {
  const s = [...xs].sort((a, b) => a - b);
  return s.length === 0 ? null : s.length % 2 ? s[(s.length - 1) / 2] : (s[s.length / 2 - 1] + s[s.length / 2]) / 2;
}

async function run() {
  check(BASE, 'set WRINKLE_PAINT_URL to the server, e.g. http://127.0.0.1:8478');
  const browser = await chromium.launch({ executablePath: CHROMIUM, headless: true, args: CHROME_ARGS, timeout: WAIT_MS });
  const pageErrors = [];
  try {
    const page = await browser.newPage({ viewport: { width: 1400, height: 1000 } });
    page.on('pageerror', (e) => pageErrors.push(`page error: ${e.message}`));
    page.on('console', (m) => {
      // Failed requests are reported by the response listener, with their address.
      if (m.type() === 'error' && !m.text().startsWith('Failed to load resource')) pageErrors.push(`console: ${m.text()}`);
    });
    page.on('response', (r) => {
      if (r.status() >= 400 && !r.url().endsWith('/favicon.ico')) pageErrors.push(`HTTP ${r.status()} for ${r.url()}`);
    });
    page.setDefaultTimeout(WAIT_MS);

    // a. The page shows a first frame.
    await page.goto(`${BASE}/`, { timeout: WAIT_MS });
    await waitProbe(page, 'the first frame', () => window.wrinklePaint && window.wrinklePaint.framesReceived >= 1);
    for (const id of ['view', 'channel', 'color', 'value', 'radius', 'hardness', 'opacity', 'spacing', 'object-space',
      'eraser', 'mirror', 'undo', 'redo', 'save', 'status', 'atlas']) {
      check(await page.$(`#${id}`), `the page lacks #${id}`);
    }

    // b. The camera on the sphere's front (+z), the atlas before painting.
    const state = await getJson('/api/state');
    for (const f of ['width', 'height', 'channels', 'atlas_size', 'camera', 'undo', 'redo']) {
      check(f in state, `GET /api/state lacks "${f}": ${JSON.stringify(state)}`);
    }
    // A server that was painted before (a rerun) goes back to the atlas it loaded.
    for (let k = 0; k < Number(state.undo) && k < 1000; k++) {
      if ((await postJson('/api/undo', {})).texels === 0) break;
    }
    const camState = await postJson('/api/camera', { yaw: 0, pitch: 0, distance: 4, target: [0, 0, 0] });
    check(camState && camState.camera && Math.abs(camState.camera.distance - 4) < 1e-6 && Math.abs(camState.camera.yaw) < 1e-6,
      `POST /api/camera did not answer the state with the new camera: ${JSON.stringify(camState)}`);
    const before = await getPng('/api/atlas/color.png');

    // c. A fresh page (it takes the camera from the state), the brush, a drag across the middle row.
    await page.reload({ timeout: WAIT_MS });
    await waitProbe(page, 'the first frame after reloading',
      () => window.wrinklePaint && window.wrinklePaint.framesReceived >= 1 && window.wrinklePaint.connected);
    const view = await viewToPage(page);
    check(view.box.w === state.width && view.box.h === state.height,
      `#view is ${view.box.w}x${view.box.h} pixels, the state's view ${state.width}x${state.height}`);
    await setInput(page, 'channel', 'color');
    await setInput(page, 'color', '#ff0000');
    await setInput(page, 'object-space', false);
    await setInput(page, 'radius', 20);
    await setInput(page, 'hardness', 1);
    await setInput(page, 'opacity', 1);
    await setInput(page, 'eraser', false);
    await setInput(page, 'mirror', false);
    const framesBefore = (await probe(page)).framesReceived;
    await page.evaluate(() => window.wrinklePaint.lastStrokeTexels = 0);
    const row = view.box.h / 2;
    const x0 = view.box.w * 0.35;
    const x1 = view.box.w * 0.65;
    await page.mouse.move(...view.at(x0, row));
    await page.mouse.down();
    await page.mouse.move(...view.at(x1, row), { steps: 10 });
    await page.mouse.up();
    await waitProbe(page, 'the stroke to change texels', () => window.wrinklePaint.lastStrokeTexels > 0);
    await waitProbe(page, 'the frames of the stroke', (n) => window.wrinklePaint.framesReceived >= n + 2, framesBefore);
    const afterStroke = await probe(page);

    // d. The texels the stroke changed lie where the drag crossed the sphere.
    const painted = await getPng('/api/atlas/color.png');
    check(painted.width === before.width && painted.height === before.height, 'the atlas changed size');
    const W = painted.width;
    const H = painted.height;
    const texel = (img, i, j) => {
      const k = (j * W + i) * 4;
      return [img.data[k], img.data[k + 1], img.data[k + 2], img.data[k + 3]];
    };
    let changed = 0;
    let red = 0;
    let uMin = Infinity;
    let uMax = -Infinity;
    let vMin = Infinity;
    let vMax = -Infinity;
    const strays = [];
    for (let j = 0; j < H; j++) {
      for (let i = 0; i < W; i++) {
        const a = texel(before, i, j);
        const b = texel(painted, i, j);
        if (a[0] === b[0] && a[1] === b[1] && a[2] === b[2] && a[3] === b[3]) continue;
        changed += 1;
        const u = (i + 0.5) / W;
        const v = 1 - (j + 0.5) / H;
        uMin = Math.min(uMin, u);
        uMax = Math.max(uMax, u);
        vMin = Math.min(vMin, v);
        vMax = Math.max(vMax, v);
        if (Math.abs(v - 0.5) > 0.12 || Math.abs(u - 0.75) >= 0.2) {
          if (strays.length < 5) strays.push({ i, j, u: +u.toFixed(4), v: +v.toFixed(4) });
        }
        if (b[0] > 200 && b[1] < 40 && b[2] < 40) red += 1;
      }
    }
    check(changed > 0, 'the stroke changed no texel of the colour atlas');
    check(strays.length === 0,
      `changed texels away from the drag (expected v = 0.5 +- 0.12, |u - 0.75| < 0.2): ${JSON.stringify(strays)} ` +
      `(of ${changed}; u in [${uMin.toFixed(3)}, ${uMax.toFixed(3)}], v in [${vMin.toFixed(3)}, ${vMax.toFixed(3)}])`);
    check(uMax - uMin >= 0.08, `the changed texels span u ${uMin.toFixed(3)}..${uMax.toFixed(3)}, less than 0.08`);
    check(red > 0, 'no changed texel is red (R > 200, G < 40, B < 40)');
    // The back of the sphere, (u, v) = (0.25, 0.5), is untouched.
    const iBack = Math.floor(0.25 * W);
    for (const j of [Math.floor(0.5 * H) - 1, Math.floor(0.5 * H)]) {
      const a = texel(before, iBack, j);
      const b = texel(painted, iBack, j);
      check(a.every((x, k) => x === b[k]), `the back of the sphere (texel ${iBack}, ${j}) changed: ${a} -> ${b}`);
    }

    // e. The view shows the paint at the middle of the drag.
    const frame = await getPng('/api/frame.png');
    check(frame.width === state.width && frame.height === state.height,
      `GET /api/frame.png is ${frame.width}x${frame.height}, the view ${state.width}x${state.height}`);
    const fc = Math.floor(frame.height / 2) * frame.width + Math.floor(frame.width / 2);
    const centre = [frame.data[4 * fc], frame.data[4 * fc + 1], frame.data[4 * fc + 2]];
    check(centre[0] > 2 * centre[1] && centre[0] > 20, `the view's centre is not red after painting: rgb ${centre}`);

    // f. Undo gives back the atlas as it was, redo the painted one.
    const t0 = Date.now();
    await page.click('#undo');
    await until('undo to restore the atlas exactly', async () => sameImage(await getPng('/api/atlas/color.png'), before));
    const undoMs = Date.now() - t0;
    const t1 = Date.now();
    await page.click('#redo');
    await until('redo to give back the painted atlas', async () => sameImage(await getPng('/api/atlas/color.png'), painted));
    const redoMs = Date.now() - t1;

    // g. Stroke-to-frame latency: a second stroke, one point at a time, each waited for; then undone.
    const latencies = [];
    const row2 = view.box.h * 0.4;
    let p = await probe(page);
    await page.mouse.move(...view.at(view.box.w * 0.45, row2));
    await page.mouse.down();
    await waitProbe(page, 'the frame of the first point', (n) => window.wrinklePaint.framesReceived > n, p.framesReceived);
    for (let k = 1; k <= 6; k++) {
      p = await probe(page);
      await page.mouse.move(...view.at(view.box.w * (0.45 + 0.02 * k), row2));
      await waitProbe(page, `the frame of stroke point ${k}`, (n) => window.wrinklePaint.framesReceived > n, p.framesReceived);
      latencies.push((await probe(page)).lastLatencyMs);
    }
    p = await probe(page);
    await page.evaluate(() => window.wrinklePaint.lastStrokeTexels = 0);
    await page.mouse.up();
    await waitProbe(page, 'the second stroke to end', (n) => window.wrinklePaint.lastStrokeTexels > 0
      && window.wrinklePaint.framesReceived > n, p.framesReceived);
    const endLatency = (await probe(page)).lastLatencyMs;
    check(latencies.every((l) => Number.isFinite(l) && l > 0), `latencies not measured: ${latencies}`);
    await page.keyboard.press('Control+z');
    await until('Ctrl+Z to undo the second stroke', async () => sameImage(await getPng('/api/atlas/color.png'), painted));

    check(pageErrors.length === 0, `the page reported errors: ${pageErrors.join(' | ')}`);
    const final = await probe(page);
    return {
      ok: true,
      view: [state.width, state.height],
      atlas: [W, H],
      texels: afterStroke.lastStrokeTexels,
      changed_texels: changed,
      red_texels: red,
      u_range: [+uMin.toFixed(4), +uMax.toFixed(4)],
      v_range: [+vMin.toFixed(4), +vMax.toFixed(4)],
      centre_rgb: centre,
      stroke_latency_ms: +median(latencies).toFixed(1),
      stroke_latency_max_ms: Math.max(...latencies),
      stroke_end_latency_ms: endLatency,
      undo_ms: undoMs,
      redo_ms: redoMs,
      frames: final.framesReceived,
    };
  } catch (e) {
    if (pageErrors.length > 0 && !e.message.startsWith('the page reported')) {
      e.message += ` [the page reported: ${pageErrors.join(' | ')}]`;
    }
    throw e;
  } finally {
    await browser.close().catch(() => {});
  }
}

const guard = setTimeout(() => {
  console.error(`paint.test.mjs: FAILED: the test took more than ${OVERALL_MS / 1000} s`);
  process.exit(1);
}, OVERALL_MS);

run().then(
  (summary) => {
    clearTimeout(guard);
    console.log(JSON.stringify(summary));
    process.exit(0);
  },
  (e) => {
    clearTimeout(guard);
    console.error(`paint.test.mjs: FAILED: ${e && e.message ? e.message : e}`);
    process.exit(1);
  },
);
