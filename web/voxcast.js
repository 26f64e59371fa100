// Voxcast's page loader: records every error for the page's test, picks the build the browser
// can draw with (WebGPU where it offers an adapter, else WebGL2; `?gpu=webgl2` or `?gpu=webgpu`
// chooses), starts it, and hands it the files a student picks or drops on the page.

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

/** Which of the two builds this browser runs: WebGPU needs an adapter, not just `navigator.gpu`. */
async function chooseGraphics() {
  const asked = new URLSearchParams(location.search).get('gpu');
  if (asked === 'webgl2' || asked === 'webgpu') return asked;
  try {
    if (navigator.gpu && (await navigator.gpu.requestAdapter())) return 'webgpu';
  } catch (_) { /* no WebGPU: WebGL2 below */ }
  return 'webgl2';
}

/** Reads `files` (a FileList) and hands them to the sandbox for `purpose`. */
async function handOver(wasm, purpose, files) {
  const list = Array.from(files || []);
  if (list.length === 0) return;
  const names = list.map((f) => f.name);
  const bytes = await Promise.all(list.map(async (f) => new Uint8Array(await f.arrayBuffer())));
  wasm.voxcast_receive_files(purpose, names, bytes);
}

async function start() {
  const graphics = await chooseGraphics();
  window.voxcastGraphics = graphics;
  let wasm;
  try {
    wasm = await import(`./${graphics}/voxcast.js`);
    await wasm.default({ module_or_path: `./${graphics}/voxcast_bg.wasm` });
  } catch (e) {
    // winit ends its start with an exception it uses for control flow; anything else failed.
    if (!String(e).includes('Using exceptions for control flow')) {
      fail(`Voxcast could not start in this browser: ${e}`);
      throw e;
    }
  }
  loading.hidden = true;
  window.voxcastStatus = () => JSON.parse(wasm.voxcast_status());

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

  // Files dropped anywhere on the page open as a volume.
  let over = 0;
  document.addEventListener('dragenter', (e) => { e.preventDefault(); over += 1; dropHint.hidden = false; });
  document.addEventListener('dragleave', () => { over = Math.max(0, over - 1); dropHint.hidden = over > 0 ? false : true; });
  document.addEventListener('dragover', (e) => e.preventDefault());
  document.addEventListener('drop', (e) => {
    e.preventDefault();
    over = 0;
    dropHint.hidden = true;
    handOver(wasm, 'volume', e.dataTransfer && e.dataTransfer.files);
  });
  document.getElementById('voxcast-canvas').focus();
}

start();
