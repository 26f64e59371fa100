// Voxcast's page loader: records every error for the page's test, picks the build the browser
// can draw with (WebGPU where it offers an adapter, else WebGL2; `?gpu=webgl2` or `?gpu=webgpu`
// chooses), starts it, watches that it draws (falling back to WebGL2 where WebGPU stops), and
// hands it the files a student picks or drops on the page (a folder
// too), the levels `?levels=URL` names (with the data sets they name, from this site), and a
// level carried in the address (`#level=…`, the level editor's Copy link).

const errors = [];
window.voxcastErrors = errors;
const keep = (what) => errors.push(String(what));
const consoleError = console.error.bind(console);
console.error = (...args) => { keep(args.join(' ')); consoleError(...args); };
window.addEventListener('error', (e) => keep(e.message || e.error));
window.addEventListener('unhandledrejection', (e) => keep(e.reason));

const loading = document.getElementById('voxcast-loading');
const dropHint = document.getElementById('voxcast-drop');
const fail = (text) => {
  const box = document.getElementById('voxcast-error');
  box.textContent = text;
  box.hidden = false;
  loading.hidden = true;
};

/** Shows `text` in the line above the page: `voxcast-notice` (shared with the sandbox's own
 * notices) or, for the loader's switch of build, a line of its own that nothing overwrites. */
const notify = (text, id = 'voxcast-notice') => {
  const notice = document.getElementById(id);
  notice.textContent = text;
  notice.hidden = false;
};

/** The build the address asks for (`?gpu=`), if any. */
function askedGraphics() {
  const asked = new URLSearchParams(location.search).get('gpu');
  return asked === 'webgl2' || asked === 'webgpu' ? asked : null;
}

/** The browser's WebGPU adapter as the sandbox reads it (`voxcastAdapter`): its name in words
 * and whether it is the browser's fallback, a software rasterizer (wgpu names neither in a
 * browser, and the sandbox gives a software rasterizer the CPU live view, as on the desktop).
 * Null where there is none. */
async function webgpuAdapter() {
  try {
    const adapter = navigator.gpu && (await navigator.gpu.requestAdapter());
    if (!adapter) return null;
    const info = adapter.info || {};
    const name = [info.vendor, info.architecture, info.device, info.description]
      .filter(Boolean).join(' ');
    return { name, fallback: Boolean(info.isFallbackAdapter ?? adapter.isFallbackAdapter) };
  } catch (_) {
    return null; // no WebGPU
  }
}

/** Which of the two builds this browser runs (WebGPU needs an adapter, not just
 * `navigator.gpu`), and the promise of the WebGPU adapter where that build runs: where the
 * address chose the build, the adapter is asked for while the module downloads. */
async function chooseGraphics() {
  const asked = askedGraphics();
  if (asked) return [asked, asked === 'webgpu' ? webgpuAdapter() : Promise.resolve(null)];
  const adapter = await webgpuAdapter();
  return adapter ? ['webgpu', Promise.resolve(adapter)] : ['webgl2', Promise.resolve(null)];
}

/** The real embedded datasets (`builtin::FILES` in the core: name and file), which the page's
 * module does not carry: the one the page opens with (`?volume=builtin:NAME`, else the bunny)
 * is fetched from `volumes/` beside it while the module downloads; the sandbox fetches another
 * the first time it is opened. One that cannot be fetched is left out: the sandbox says so. */
const VOLUME_FILES = [['bunny', 'bunny_sdf.nrrd'], ['brainsmall', 'mri_brainsmall.nrrd']];
async function fetchVolumes() {
  const asked = (new URLSearchParams(location.search).get('volume') || 'builtin:bunny')
    .replace(/^builtin:/, '').replaceAll('_', '-');
  const entry = VOLUME_FILES.find(([n]) => n === asked);
  if (!entry) return {};
  const name = entry[1];
  try {
    const r = await fetch(`./volumes/${name}`);
    if (r.ok) return { [name]: new Uint8Array(await r.arrayBuffer()) };
    console.warn(`volumes/${name}: ${r.status} ${r.statusText}`);
  } catch (e) {
    console.warn(`volumes/${name}: ${e}`);
  }
  return {};
}

/** Reads `files` (File objects) and hands them to the sandbox for `purpose`; a file picked
 * in a folder keeps its path inside it. A volume's files are handed over unread: the sandbox
 * reads them in pieces, with progress and Cancel, and refuses one larger than it can hold. */
async function handOver(wasm, purpose, files) {
  const list = Array.from(files || []);
  if (list.length === 0) return;
  const names = list.map((f) => f.relativePath || f.webkitRelativePath || f.name);
  if (purpose === 'volume') {
    wasm.voxcast_receive_volume(names, list);
    return;
  }
  const bytes = await Promise.all(list.map(async (f) => new Uint8Array(await f.arrayBuffer())));
  wasm.voxcast_receive_files(purpose, names, bytes);
}

/** What dropped files are for: level files (with the data sets they name), a class's answer
 * files, or a volume. */
function purposeOf(files) {
  const names = files.map((f) => f.name.toLowerCase());
  if (names.some((n) => n.endsWith('.json'))) return 'levels';
  if (names.length > 0 && names.every((n) => n.endsWith('.csv'))) return 'answers';
  if (names.length > 0 && names.every((n) => n.endsWith('.rayvis'))) return 'rays';
  return 'volume';
}

/** The files a drop holds, a dropped folder's files inside it too (each with its path). */
async function droppedFiles(transfer) {
  const entries = Array.from(transfer.items || [])
    .map((i) => (i.webkitGetAsEntry ? i.webkitGetAsEntry() : null))
    .filter((e) => e);
  if (entries.length === 0) return Array.from(transfer.files || []);
  const out = [];
  const walk = async (entry) => {
    if (entry.isFile) {
      const file = await new Promise((ok, no) => entry.file(ok, no));
      file.relativePath = entry.fullPath.replace(/^\//, '');
      out.push(file);
    } else if (entry.isDirectory) {
      const reader = entry.createReader();
      for (;;) {
        const batch = await new Promise((ok, no) => reader.readEntries(ok, no));
        if (batch.length === 0) break;
        for (const e of batch) await walk(e);
      }
    }
  };
  for (const e of entries) await walk(e);
  return out;
}

/** `?levels=URL`: the level file (or a list of level files' URLs) fetched from this site, with
 * the data sets and transfer functions each names beside it, handed over as `levels`. */
async function fetchLevels(wasm, url) {
  const here = (u) => new URL(u, location.href);
  const get = async (u) => {
    const r = await fetch(u);
    if (!r.ok) throw new Error(`${u}: ${r.status} ${r.statusText}`);
    return new Uint8Array(await r.arrayBuffer());
  };
  const first = here(url);
  if (first.origin !== location.origin) {
    throw new Error(`${url} is on another site: levels are read from this page's own site`);
  }
  const text = new TextDecoder().decode(await get(first));
  const list = JSON.parse(text);
  const levels = Array.isArray(list) ? list.map((u) => new URL(u, first)) : [first];
  const names = [];
  const bytes = [];
  const seen = new Set();
  const add = async (u) => {
    const key = u.href;
    if (seen.has(key) || u.origin !== location.origin) return;
    seen.add(key);
    names.push(key);
    bytes.push(await get(u));
  };
  for (const level of levels) {
    await add(level);
    const parsed = JSON.parse(new TextDecoder().decode(bytes[bytes.length - 1]));
    for (const name of filesNamed(parsed)) await add(new URL(name, level));
  }
  wasm.voxcast_receive_files('levels', names, bytes);
}

/** The data sets and transfer-function files a level names (not built-ins or presets). */
function filesNamed(level) {
  const names = [];
  const scenes = [level.scene || {}, ...(level.steps || []).map((s) => s.scene || {})];
  for (const s of scenes) {
    for (const name of [s.volume, s.transfer]) {
      const file = typeof name === 'string' && !/^(builtin|density):/.test(name);
      const json = typeof name === 'string' && name.toLowerCase().endsWith('.json');
      if (file && (name === s.volume || json)) names.push(name);
    }
  }
  return names;
}

/** `#level=…`: the level the link carries (deflated, base64url), handed over with the files it
 * names on this page's own site, fetched first (a link carries no data set; one that cannot be
 * fetched is left out, and the level says so when it opens). */
async function openLink(wasm, page, fragment) {
  const names = [page];
  const bytes = [new TextEncoder().encode(fragment)];
  try {
    const b64 = fragment.slice('level='.length).replace(/-/g, '+').replace(/_/g, '/');
    const packed = Uint8Array.from(atob(b64 + '='.repeat((4 - (b64.length % 4)) % 4)), (c) => c.charCodeAt(0));
    const stream = new Blob([packed]).stream().pipeThrough(new DecompressionStream('deflate-raw'));
    const level = JSON.parse(await new Response(stream).text());
    for (const name of new Set(filesNamed(level))) {
      const u = new URL(name, page);
      if (u.origin !== location.origin) continue;
      const r = await fetch(u);
      if (!r.ok) continue;
      names.push(u.href);
      bytes.push(new Uint8Array(await r.arrayBuffer()));
    }
  } catch (e) {
    // A damaged link: the sandbox reads the fragment itself and says what is wrong.
  }
  wasm.voxcast_receive_files('level-link', names, bytes);
}

/** How long the started sandbox may go without drawing a frame while the page is shown before
 * the loader counts it as stopped (at rest it still draws one every 100 ms: REST_WAIT). */
const STALL_MS = 8000;

/** Watches the started build: where it stops drawing (no new frame for STALL_MS while the page
 * is shown: an adapter that cannot draw, a lost device, a shader the driver refused), the
 * WebGPU build the loader chose gives way to the WebGL2 one — the page opens again with
 * `?gpu=webgl2&fallback=webgpu`, the level progress kept in the browser — and otherwise the
 * page says what to try. */
function watch(wasm, graphics) {
  let last = -1;
  let since = performance.now();
  let tick = since;
  const timer = setInterval(() => {
    // A late tick means the page's one thread was busy (a large volume made ready in one piece): that is
    // work, not a stop, so the wait starts again.
    const now = performance.now();
    const late = now - tick > 2000;
    tick = now;
    if (document.visibilityState !== 'visible' || late) {
      since = now;
      return;
    }
    let frames = last;
    try { frames = JSON.parse(wasm.voxcast_status()).frames; } catch (_) { /* stopped */ }
    if (frames !== last) {
      last = frames;
      since = now;
      return;
    }
    if (now - since < STALL_MS) return;
    clearInterval(timer);
    if (graphics === 'webgpu' && !askedGraphics()) {
      const next = new URL(location.href);
      next.searchParams.set('gpu', 'webgl2');
      next.searchParams.set('fallback', 'webgpu');
      location.replace(next.href);
      return;
    }
    fail(`Voxcast stopped drawing with ${graphics === 'webgpu' ? 'WebGPU' : 'WebGL2'} in this browser `
      + `(no new frame for ${STALL_MS / 1000} seconds). Reload the page to try again; `
      + (graphics === 'webgpu'
        ? 'open it without "gpu=webgpu" in the address to use WebGL2, which every browser has; '
        : '')
      + 'otherwise try another browser (Chrome, Edge, Firefox or Safari, up to date) and check that '
      + "the browser's hardware acceleration is on.");
  }, 500);
}

async function start() {
  if (new URLSearchParams(location.search).get('fallback') === 'webgpu') {
    notify('This browser offered WebGPU but drew nothing with it: Voxcast switched to WebGL2.',
      'voxcast-switched');
  }
  const [graphics, adapter] = await chooseGraphics();
  window.voxcastGraphics = graphics;
  let wasm;
  try {
    // The module and the datasets download side by side; the sandbox takes the datasets
    // (`voxcastVolumes`) as it starts.
    const module = fetch(`./${graphics}/voxcast_bg.wasm`);
    const volumes = fetchVolumes();
    wasm = await import(`./${graphics}/voxcast.js`);
    window.voxcastVolumes = await volumes;
    window.voxcastAdapter = await adapter;
    await wasm.default({ module_or_path: module });
  } catch (e) {
    // winit ends its start with an exception it uses for control flow; anything else failed.
    if (!String(e).includes('Using exceptions for control flow')) {
      fail(`Voxcast could not start in this browser: ${e}`);
      throw e;
    }
  }
  loading.hidden = true;
  window.voxcastStatus = () => JSON.parse(wasm.voxcast_status());
  watch(wasm, graphics);
  // WebGL2 can lose its context (graphics memory full after a large volume, a driver reset):
  // the page then stays blank while the sandbox's frames go on, which `watch` cannot see.
  document.getElementById('voxcast-canvas').addEventListener('webglcontextlost', () => {
    fail('The browser took back the graphics Voxcast draws with (WebGL2 lost its context, '
      + 'often for lack of graphics memory after a large volume), so the page can no longer '
      + "draw. Reload it to start again; a smaller volume, or Voxcast's desktop app, avoids it.");
  });

  // The sandbox asks for a file with `voxcastPick(purpose, accept)` (Open… in its panels).
  const picker = document.createElement('input');
  picker.type = 'file';
  picker.multiple = true;
  picker.hidden = true;
  document.body.appendChild(picker);
  let pickPurpose = 'volume';
  picker.addEventListener('change', () => {
    handOver(wasm, pickPurpose, picker.files).finally(() => { picker.value = ''; });
  });
  window.voxcastPick = (purpose, accept) => {
    pickPurpose = purpose;
    picker.accept = accept;
    picker.click();
  };

  // Files dropped anywhere on the page: a volume opens; level files (and a folder of them, with
  // their data sets) join the levels list; a class's answer files become a report.
  let over = 0;
  document.addEventListener('dragenter', (e) => { e.preventDefault(); over += 1; dropHint.hidden = false; });
  document.addEventListener('dragleave', () => { over = Math.max(0, over - 1); dropHint.hidden = over > 0 ? false : true; });
  document.addEventListener('dragover', (e) => e.preventDefault());
  document.addEventListener('drop', (e) => {
    e.preventDefault();
    over = 0;
    dropHint.hidden = true;
    if (!e.dataTransfer) return;
    droppedFiles(e.dataTransfer).then((files) => handOver(wasm, purposeOf(files), files));
  });
  document.getElementById('voxcast-canvas').focus();

  // Levels the address names, and a level it carries.
  const levels = new URLSearchParams(location.search).get('levels');
  if (levels) {
    fetchLevels(wasm, levels).catch((e) => {
      notify(`The levels of ?levels= could not be read: ${e.message || e}`);
    });
  }
  if (location.hash.startsWith('#level=')) {
    openLink(wasm, location.href.split('#')[0], location.hash.slice(1));
  }
}

start();
