// The page of `brdfbake serve` (docs/SERVICE.md, "The web page"): plain JavaScript, no framework, no
// build step. Every call goes to the server's own JSON API with the token (if the server has one) in
// the Authorization header, never in a URL; the token is kept in sessionStorage (this tab only).
// The option forms are generated from GET /v1/bake/options (the schema `brdfbake kinds --json` and
// `brdfbake bake --help` come from), so a new option appears here by itself.
'use strict';

const TOKEN_KEY = 'brdfbake-token';
const MAIN_OPTIONS = ['environment', 'scene', 'target'];
// Presets: values given to options of the schema (options the schema lacks are skipped); production
// leaves every option at its default, which is the target's file set (docs/ENGINES.md).
const PRESETS = {
  draft: { chain_size: 64, min_size: 8, lut_size: 32, fresnel_size: 32, thin_film_size: 32, chain_max_error: 0.05 },
  production: {},
};
const PROGRESS_POLL_MS = 200;   // the progress bars' refresh while a job runs
const SERVER_POLL_MS = 2000;    // devices and jobs

const state = {
  token: sessionStorage.getItem(TOKEN_KEY) || '',
  options: [],      // GET /v1/bake/options
  devices: [],
  job: null,        // {id, tables, finished}
  serverTimer: 0,
  uploads: {},      // "upload:NAME" -> the file's name on the user's machine (its command line reads that)
};

const $ = (id) => document.getElementById(id);

function el(tag, attrs = {}, ...children) {
  const e = document.createElement(tag);
  for (const [k, v] of Object.entries(attrs)) {
    if (v === undefined || v === null || v === false) continue;
    if (k === 'text') e.textContent = v;
    else if (k === 'class') e.className = v;
    else if (k.startsWith('on')) e.addEventListener(k.slice(2), v);
    else e.setAttribute(k, v === true ? '' : String(v));
  }
  for (const c of children) if (c !== null && c !== undefined) e.append(c);
  return e;
}

class ApiError extends Error {
  constructor(status, message) {
    super(message);
    this.status = status;
  }
}

async function api(path, init = {}) {
  const headers = new Headers(init.headers || {});
  if (state.token) headers.set('Authorization', 'Bearer ' + state.token);
  return fetch(path, { ...init, headers, cache: 'no-store' });
}

// The body of an answer as JSON; a refusal throws ApiError with the API's one-line error.
async function apiJson(path, init) {
  const res = await api(path, init);
  let body = null;
  try {
    body = await res.json();
  } catch (e) {
    body = null;
  }
  if (!res.ok) throw new ApiError(res.status, body && body.error ? body.error : `HTTP ${res.status} from ${path}`);
  return body;
}

function postJson(path, body) {
  return apiJson(path, { method: 'POST', headers: { 'Content-Type': 'application/json' }, body: JSON.stringify(body) });
}

function humanBytes(n) {
  if (typeof n !== 'number') return '';
  if (n >= 1 << 30) return (n / (1 << 30)).toFixed(1) + ' GiB';
  if (n >= 1 << 20) return (n / (1 << 20)).toFixed(1) + ' MiB';
  if (n >= 1 << 10) return (n / (1 << 10)).toFixed(1) + ' KiB';
  return n + ' B';
}

function fileUrl(id, kind, path) {
  return `/v1/jobs/${encodeURIComponent(id)}/${kind}/` + path.split('/').map(encodeURIComponent).join('/');
}

// ---- The token ----------------------------------------------------------------------------------

function askToken(message) {
  $('token-section').hidden = false;
  $('token-error').textContent = message || '';
  $('server-status').textContent = 'this server needs its token';
  $('token').focus();
}

async function useToken(event) {
  event.preventDefault();
  const given = $('token').value.trim();
  state.token = given;
  try {
    const health = await apiJson('/v1/health');
    sessionStorage.setItem(TOKEN_KEY, given);
    $('token-section').hidden = true;
    $('token-error').textContent = '';
    connected(health);
  } catch (e) {
    state.token = '';
    sessionStorage.removeItem(TOKEN_KEY);
    $('token-error').textContent = e.message;
    $('token').setAttribute('aria-invalid', 'true');
  }
}

// ---- The options form, from the schema -------------------------------------------------------------

// Uploads (POST /v1/uploads: the file's bytes as the body, under the server's --max-upload, 64 MiB by default): the server
// reads the file as a bake would and answers the name to give the field ("upload:...").
const UPLOADS = { environment: '.hdr,.exr,.png,.ktx2', scene: '.gltf,.glb' };

function uploadInput(name) {
  const input = el('input', { id: 'upload-' + name, type: 'file', accept: UPLOADS[name], 'aria-describedby': 'error-' + name });
  input.addEventListener('change', async () => {
    const file = input.files[0];
    if (!file) return;
    clearErrors();
    $('help-' + name).dataset.uploading = 'true';
    try {
      // the server takes plain names: other characters become '_'
      const label = file.name.replace(/[^A-Za-z0-9._-]/g, '_').replace(/^\./, '_').slice(-100);
      const reply = await apiJson('/v1/uploads?name=' + encodeURIComponent(label), {
        method: 'POST', body: file, headers: { 'Content-Type': 'application/octet-stream' },
      });
      $('opt-' + name).value = reply.name;
      state.uploads[reply.name] = file.name;
    } catch (e) {
      $('error-' + name).textContent = e.message;
      $('field-' + name).classList.add('invalid');
    } finally {
      delete $('help-' + name).dataset.uploading;
      input.value = '';
    }
  });
  return el('label', { class: 'upload', for: 'upload-' + name }, 'or upload a file ', input);
}

function defaultText(d) {
  if (d.default !== undefined) return Array.isArray(d.default) ? d.default.join(',') : String(d.default);
  return d.default_text || '';
}

function makeField(d, datalists) {
  const id = 'opt-' + d.name;
  let input;
  if (d.type === 'flag') {
    input = el('input', { id, type: 'checkbox', name: d.name });
    input.checked = d.default === true;
  } else if (d.choices) {
    input = el('select', { id, name: d.name });
    if (d.default === undefined) input.append(el('option', { value: '', text: `(default${d.default_text ? ': ' + d.default_text : ''})` }));
    for (const c of d.choices) input.append(el('option', { value: c, text: c, selected: c === d.default }));
  } else if (d.type === 'integer' || d.type === 'number') {
    input = el('input', {
      id, name: d.name, type: 'number', inputmode: d.type === 'integer' ? 'numeric' : 'decimal',
      min: d.min_exclusive ? undefined : d.min, max: d.max, step: d.type === 'integer' ? 1 : 'any',
      placeholder: defaultText(d),
    });
  } else {
    input = el('input', { id, name: d.name, type: 'text', placeholder: defaultText(d), list: datalists[d.name], autocomplete: 'off' });
  }
  input.setAttribute('aria-describedby', `help-${d.name} error-${d.name}`);
  const label = el('label', { for: id }, d.name.replaceAll('_', ' '), ' ', el('code', { text: d.option, class: 'help' }));
  return el('div', { class: 'field', id: 'field-' + d.name }, label, input,
    el('span', { class: 'help', id: 'help-' + d.name, text: `${d.help} (${d.expects})` }),
    el('p', { class: 'field-error', id: 'error-' + d.name, role: 'alert' }));
}

function buildForm(inputs) {
  const datalists = {};
  const lists = { environment: inputs.environments || [], scene: inputs.scenes || [], device: state.devices.map((d) => ({ path: d.key })).concat([{ path: 'reference' }]) };
  for (const [name, items] of Object.entries(lists)) {
    const dl = el('datalist', { id: 'list-' + name });
    for (const it of items) dl.append(el('option', { value: it.path, text: it.bytes ? humanBytes(it.bytes) : '' }));
    document.body.append(dl);
    datalists[name] = 'list-' + name;
  }
  const main = $('main-options'), other = $('other-options');
  main.textContent = '';
  other.textContent = '';
  for (const name of MAIN_OPTIONS) {
    const d = state.options.find((o) => o.name === name);
    if (!d) continue;
    const field = makeField(d, datalists);
    if (UPLOADS[name]) field.insertBefore(uploadInput(name), field.querySelector('.field-error'));
    main.append(field);
  }
  for (const d of state.options) if (!MAIN_OPTIONS.includes(d.name)) other.append(makeField(d, datalists));
  if (!inputs.input_root) {
    $('help-environment').textContent += ' — this server has no --input-root: builtin environments only';
  }
}

// The value of an option as POST /v1/bake takes it; undefined when left at its default.
function fieldValue(d) {
  const input = $('opt-' + d.name);
  if (!input) return undefined;
  if (d.type === 'flag') return input.checked === (d.default === true) ? undefined : input.checked;
  if (d.choices) {
    const v = input.value;
    return v === '' || v === d.default ? undefined : v;
  }
  const t = input.value.trim();
  if (t === '') return undefined;
  if (d.type === 'integer' || d.type === 'number') {
    const x = Number(t);
    return Number.isFinite(x) ? x : t;
  }
  if (d.type === 'rgb' || d.type === 'range' || d.type === 'integers') {
    const parts = t.split(/[\s,]+/).filter((p) => p !== '').map(Number);
    if (parts.some((x) => !Number.isFinite(x))) return t;  // the server names what is wrong
    return parts.length === 1 ? parts[0] : parts;
  }
  return t;
}

function bakeOptions() {
  const o = {};
  for (const d of state.options) {
    const v = fieldValue(d);
    if (v !== undefined) o[d.name] = v;
  }
  return o;
}

function applyPreset(name) {
  const preset = PRESETS[name];
  for (const d of state.options) {
    if (MAIN_OPTIONS.includes(d.name)) continue;
    const input = $('opt-' + d.name);
    if (!input) continue;
    const v = preset[d.name];
    if (d.type === 'flag') input.checked = v === undefined ? d.default === true : Boolean(v);
    else if (d.choices) input.value = v === undefined ? (d.default === undefined ? '' : d.default) : v;
    else input.value = v === undefined ? '' : String(v);
  }
  clearErrors();
}

function shellQuote(s) {
  return /^[A-Za-z0-9_.,:\/+=@-]+$/.test(s) ? s : "'" + s.replaceAll("'", "'\\''") + "'";
}

// The command that bakes the same files (paths as the server reads them: under its --input-root).
// The command that bakes the same on the user's machine: an uploaded file by the name it had there
// (the server's "upload:..." names exist only on the server), said in a comment.
function bakeCommand(options) {
  const args = ['brdfbake', 'bake'];
  const notes = [];
  for (const d of state.options) {
    if (!(d.name in options)) continue;
    let v = options[d.name];
    if (typeof v === 'string' && v.startsWith('upload:')) {
      const local = state.uploads[v];
      notes.push(local ? `${d.option} is the file you uploaded as ${v}`
        : `${d.option}: ${v} is a file uploaded to the server: give its path on this machine`);
      v = local || v.slice('upload:'.length).replace(/^[0-9a-f]{12}-/, '');
    }
    if (d.type === 'flag') args.push(v ? d.option : '--no-' + d.option.slice(2));
    else args.push(d.option, shellQuote(Array.isArray(v) ? v.join(',') : String(v)));
  }
  args.push('-o', 'out');
  return args.join(' ') + notes.map((n) => '\n# ' + n).join('');
}

// ---- Errors next to their field -----------------------------------------------------------------

function clearErrors() {
  for (const e of document.querySelectorAll('#bake-form .field-error')) e.textContent = '';
  for (const e of document.querySelectorAll('#bake-form .field.invalid')) e.classList.remove('invalid');
  for (const e of document.querySelectorAll('#bake-form [aria-invalid]')) e.removeAttribute('aria-invalid');
}

// The field an API error names: "bake: chain_size: ...", "bake: tables[1].environment: ...", or the
// first option named anywhere in the line.
function fieldOfError(message) {
  const names = state.options.map((d) => d.name);
  const m = /^[^:]*: (?:tables\[\d+\]\.)?([a-z_]+)\b/.exec(message);
  if (m && names.includes(m[1])) return m[1];
  let best = null, at = Infinity;
  for (const n of names) {
    const i = message.search(new RegExp('\\b' + n + '\\b'));
    if (i >= 0 && i < at) {
      best = n;
      at = i;
    }
  }
  return best;
}

function showError(message, fallbackId = 'bake-error') {
  clearErrors();
  const name = fieldOfError(message);
  const target = name && $('error-' + name);
  if (target) {
    target.textContent = message;
    $('field-' + name).classList.add('invalid');
    $('opt-' + name).setAttribute('aria-invalid', 'true');
    if (name !== 'environment' && name !== 'scene' && name !== 'target') $('more-options').open = true;
  } else {
    $(fallbackId).textContent = message;
  }
}

// ---- Bake, dry run, copy ------------------------------------------------------------------------

async function copyText(text) {
  const pre = $('command-text');
  pre.textContent = text;
  pre.hidden = false;
  try {
    await navigator.clipboard.writeText(text);
  } catch (e) {
    // Not a secure context, or no permission: the text is shown to copy by hand.
  }
}

async function planJob() {
  const plan = await postJson('/v1/plan', bakeOptions());
  return plan;
}

async function dryRun() {
  clearErrors();
  try {
    const plan = await planJob();
    const body = $('plan-table').tBodies[0];
    body.textContent = '';
    const secs = (s) => (s === undefined ? '' : s.toFixed(2) + ' s');
    for (const t of plan.tables) {
      body.append(el('tr', {}, el('td', { class: 'mono', text: t.output }), el('td', { text: t.kind }),
        el('td', { text: secs(t.seconds) }), el('td', { text: t.bytes === undefined ? '' : humanBytes(t.bytes) }),
        el('td', { text: humanBytes(t.estimated_bytes) })));
    }
    const w = plan.estimate;
    $('plan-total').textContent = w ? 'Whole bake: about ' + secs(w.seconds) + ' (environment ' + secs(w.environment_seconds) +
      '), ' + humanBytes(w.bytes) + ' of tables; measured on the server\'s device by bakes at reduced size' +
      (w.calibration_seconds > 0 ? ' (' + secs(w.calibration_seconds) + ')' : ' (cached)') + '.' : '';
    $('plan').hidden = false;
  } catch (e) {
    showError(e.message);
  }
}

async function bake(event) {
  event.preventDefault();
  clearErrors();
  $('bake-button').disabled = true;
  try {
    const options = bakeOptions();
    const clickedAt = performance.now();
    const reply = await postJson('/v1/bake', options);
    followJob(reply.id, clickedAt, options);
  } catch (e) {
    showError(e.message);
  } finally {
    $('bake-button').disabled = false;
  }
}

// ---- A job: progress, ETA, cancel, result -------------------------------------------------------------

function progressBars(tables, progress, finished) {
  const box = $('job-progress');
  const n = progress ? progress.bakes : (tables.length || 1);
  box.textContent = '';
  for (let i = 0; i < n; ++i) {
    let fraction = 0;
    if (finished) fraction = 1;
    else if (progress) fraction = i < progress.bake ? 1 : i === progress.bake ? progress.fraction : 0;
    let label = n === tables.length ? `${tables[i].output} (${tables[i].kind})` : `bake ${i + 1} of ${n}`;
    if (progress && !finished && i === progress.bake && progress.what) label += ` — ${progress.what}`;
    const pct = Math.round(fraction * 100);
    const bar = el('progress', { max: 100, value: pct, 'aria-label': label });
    box.append(el('div', { class: 'bar' }, el('span', { class: 'mono', text: label }), bar, el('span', { text: pct + ' %' })));
  }
}

// Follows a job: `clickedAt` and `options` when this page submitted it (for the timing and the
// command), absent for a job chosen from the list.
async function followJob(id, clickedAt, options) {
  const job = { id, tables: [], finished: false, clickedAt, options };
  state.job = job;
  $('job-section').hidden = false;
  $('results-section').hidden = true;
  $('results').textContent = '';
  delete $('results').dataset.ready;
  delete $('results').dataset.seconds;
  delete $('results').dataset.firstSeconds;
  $('job-id').textContent = id;
  $('job-state').textContent = 'submitted';
  $('job-progress').textContent = '';
  $('job-error').textContent = '';
  $('job-warnings').textContent = '';
  $('job-eta').textContent = '';
  $('cancel-button').disabled = false;
  apiJson(`/v1/jobs/${encodeURIComponent(id)}/job`).then((doc) => { job.tables = doc.tables || []; }).catch(() => {});
  // A long poll answers the moment the job is finished; short polls move the bars meanwhile.
  const longPoll = async () => {
    while (!job.finished && state.job === job) {
      try {
        const s = await apiJson(`/v1/jobs/${encodeURIComponent(id)}?wait=60`);
        if (['done', 'failed', 'cancelled'].includes(s.state)) return finish(job, s);
      } catch (e) {
        $('job-error').textContent = e.message;
        return;
      }
    }
  };
  const shortPoll = async () => {
    while (!job.finished && state.job === job) {
      try {
        const s = await apiJson(`/v1/jobs/${encodeURIComponent(id)}`);
        if (job.finished || state.job !== job) return;  // the long poll answered first: this is older
        if (['done', 'failed', 'cancelled'].includes(s.state)) return finish(job, s);
        showState(job, s);
      } catch (e) {
        return;
      }
      await new Promise((r) => setTimeout(r, PROGRESS_POLL_MS));
    }
  };
  longPoll();
  shortPoll();
}

function showState(job, s) {
  $('job-state').textContent = s.state + (s.progress ? ` — ${Math.round(s.progress.overall * 100)} % overall` : '');
  progressBars(job.tables, s.progress, false);
  if (s.progress && s.progress.overall > 0.02 && s.seconds) {
    const eta = (s.seconds * (1 - s.progress.overall)) / s.progress.overall;
    $('job-eta').textContent = `about ${eta.toFixed(1)} s left (${s.seconds.toFixed(1)} s so far)`;
  } else {
    $('job-eta').textContent = s.state === 'queued' ? 'waiting for its device' : '';
  }
}

function finish(job, s) {
  if (job.finished) return;
  job.finished = true;
  $('cancel-button').disabled = true;
  $('job-eta').textContent = s.seconds !== undefined ? `${s.seconds.toFixed(2)} s on the server` : '';
  $('job-state').textContent = s.state;
  progressBars(job.tables, null, s.state === 'done');
  for (const w of s.warnings || []) $('job-warnings').append(el('li', { text: 'warning: ' + w }));
  if (s.state === 'done') showResults(job, s);
  else if (s.error) {
    $('job-error').textContent = s.error;
    if (s.state === 'failed') showError(s.error, 'job-error');  // by the field it names, if any
  }
  refreshServer();
}

async function cancelJob() {
  if (!state.job) return;
  try {
    const r = await apiJson(`/v1/jobs/${encodeURIComponent(state.job.id)}`, { method: 'DELETE' });
    $('job-state').textContent = r.note || r.state;
  } catch (e) {
    $('job-error').textContent = e.message;
  }
}

// A file of a job (or, with path null, its folder as one tar file), saved by the browser: fetched
// with the token, then handed over from memory.
async function download(id, path) {
  try {
    const res = await api(path === null ? `/v1/jobs/${encodeURIComponent(id)}/archive` : fileUrl(id, 'files', path));
    if (!res.ok) throw new ApiError(res.status, (await res.json()).error);
    const url = URL.createObjectURL(await res.blob());
    const a = el('a', { href: url, download: path === null ? `${id}.tar` : path.split('/').pop() });
    document.body.append(a);
    a.click();
    a.remove();
    setTimeout(() => URL.revokeObjectURL(url), 60000);
  } catch (e) {
    $('job-error').textContent = e.message;
  }
}

// A fraction as the page prints it (0.0123 -> "1.23 %"); the manifest keeps numbers as text.
function pct(v) {
  const x = Number(v);
  return Number.isFinite(x) ? `${(100 * x).toPrecision(3)} %` : '—';
}

function describe(f) {
  const parts = [];
  if (f.kind) parts.push(f.kind);
  if (typeof f.bytes === 'number') parts.push(humanBytes(f.bytes));
  // the error figure under its kind's name, as the manifest and the summary lines name it
  if (f.table) parts.push(`${f.error_name || 'error_bound'} ` + (f.bound_text || '— (not measured)'));
  // An engine file's delivered error: the file decoded as the engine decodes it, the manifest's names
  if (f.engine_entry) {
    const e = f.engine_entry;
    if (e.format) parts.push(e.format);
    parts.push(typeof e.error_rms_rel === 'number'
      ? `error_rms_rel ${e.error_rms_rel.toPrecision(2)}, error_max_rel ${e.error_max_rel.toPrecision(2)}`
      : 'no texel values (text)');
  }
  if (typeof f.seconds === 'number') parts.push(`${f.seconds.toFixed(2)} s`);
  return parts.join(' · ');
}

function showResults(job, s) {
  const box = $('results');
  box.textContent = '';
  const manifest = s.manifest || {};
  // Each file's figure under its name as the command line prints it (error_bound_text: rounded up to
  // three digits); error_bounds: an older server's, the text alone.
  const figures = s.error_figures || {};
  const bounds = s.error_bounds || {};
  const figureText = (f) => {
    const e = figures[f.path];
    return e ? e[e.error_name] : bounds[f.path];
  };
  const files = (manifest.files || []).map((f) => ({ ...f, picture: true, table: true, bound_text: figureText(f) }));
  const engine = manifest.engine || {};
  // Filament's KTX1 cubes (R11F_G11F_B10F, RGBM) are drawn too: the view code reads them.
  const entries = {};
  for (const e of engine.file_entries || []) entries[e.path] = e;
  for (const p of engine.files || []) {
    const e = entries[p];
    files.push({ path: p, kind: `${engine.target} engine file`, picture: /\.ktx$/i.test(p), engine_entry: e, bytes: e ? e.bytes : undefined });
  }
  // The material preview (the bake option "preview", docs/PREVIEW.md): its sheet drawn like any file,
  // captioned with the split-sum's error against the reference; its EXRs and JSON listed.
  const preview = manifest.preview || {};
  for (const p of preview.files || []) {
    const sheet = p === preview.sheet;
    const numbers = `material preview (${preview.target}): split-sum vs reference, relative RMS ` +
      `${pct(preview.error_rms_median)} median, ${pct(preview.error_rms_max)} worst sphere; ` +
      `reference within ${pct(preview.reference_bound_max)}` +
      // the error's shares: the engine's split sum from an ideal bake vs the reference, the files vs that ideal
      (preview.engine_share_median !== undefined
        ? `; engine share ${pct(preview.engine_share_median)} median, ${pct(preview.engine_share_max)} worst, ` +
          `bake share ${pct(preview.bake_share_median)} median, ${pct(preview.bake_share_max)} worst (the difference ` +
          `images add up: split-sum - reference = (split-sum - ideal) + (ideal - reference))`
        : '') +
      (preview.held_to ? `; the split-sum emulation held to: ${preview.held_to}` : '');
    files.push({ path: p, kind: sheet ? numbers : 'material preview', picture: sheet });
  }
  files.push({ path: 'manifest.json', kind: 'manifest', picture: false });
  const pictures = [];
  for (const f of files) {
    const item = el('div', { class: 'file', 'data-path': f.path },
      el('h3', { class: 'mono', text: f.path }),
      el('p', { text: describe(f) }),
      el('button', { type: 'button', class: 'download', 'data-path': f.path, onclick: () => download(job.id, f.path) }, 'Download ', el('span', { class: 'mono', text: f.path.split('/').pop() })));
    if (f.picture) {
      const img = el('img', { class: 'view', alt: `contact sheet of ${f.path} (brdfbake view)` });
      const note = el('p', { class: 'note' });
      item.append(img, note);
      pictures.push(showPicture(job, f.path, img, note));
    }
    box.append(item);
  }
  $('results-section').hidden = false;
  Promise.all(pictures).then(() => {
    // From the click on Bake to every picture shown (docs/SERVICE.md, "The web page").
    if (job.clickedAt !== undefined) box.dataset.seconds = ((performance.now() - job.clickedAt) / 1000).toFixed(3);
    box.dataset.ready = 'true';
  });
}

async function showPicture(job, path, img, note) {
  try {
    const res = await api(fileUrl(job.id, 'view', path));
    if (!res.ok) throw new ApiError(res.status, (await res.json()).error);
    const url = URL.createObjectURL(await res.blob());
    await new Promise((resolve) => {
      img.onload = resolve;
      img.onerror = resolve;
      img.src = url;
    });
    // From the click on Bake to the first picture shown (the measure).
    const box = $('results');
    if (job.clickedAt !== undefined && !box.dataset.firstSeconds)
      box.dataset.firstSeconds = ((performance.now() - job.clickedAt) / 1000).toFixed(3);
  } catch (e) {
    img.remove();
    note.textContent = 'no picture: ' + e.message;
  }
}

async function copyJob(fromResult) {
  try {
    const doc = fromResult && state.job ? await apiJson(`/v1/jobs/${encodeURIComponent(state.job.id)}/job`) : (await planJob()).job;
    await copyText(JSON.stringify(doc, null, 2));
  } catch (e) {
    showError(e.message);
  }
}

// ---- The server: devices and jobs -----------------------------------------------------------------

function when(t) {
  return t ? new Date(t * 1000).toLocaleString() : '';
}

async function refreshServer() {
  try {
    const [devices, jobs] = await Promise.all([apiJson('/v1/devices'), apiJson('/v1/jobs?limit=20')]);
    state.devices = devices.devices;
    const db = $('devices').tBodies[0];
    db.textContent = '';
    for (const d of devices.devices)
      db.append(el('tr', {}, ...[d.key, d.name, d.type, d.warm ? 'yes' : 'no', d.busy ? 'yes' : 'no', d.running || '', d.queued, d.busy_seconds.toFixed(1), `${Math.round(100 * (d.load || 0))} %`].map((v) => el('td', { text: String(v) }))));
    const jb = $('jobs').tBodies[0];
    jb.textContent = '';
    for (const j of jobs.jobs) {
      const open = el('button', { type: 'button', onclick: () => followJob(j.id) }, 'show');
      jb.append(el('tr', {}, el('td', { class: 'mono', text: j.id }), el('td', { text: j.source }), el('td', { text: j.state }),
        el('td', { text: j.device }), el('td', { text: when(j.submitted) }), el('td', { text: j.seconds !== undefined ? j.seconds.toFixed(2) : '' }), el('td', {}, open)));
    }
  } catch (e) {
    $('server-status').textContent = 'server: ' + e.message;
  }
}

// ---- Start ----------------------------------------------------------------------------------------

async function connected(health) {
  $('server-status').textContent = `brdfbake ${health.version} · ${health.devices} device(s)${health.warm ? ', warm' : ''} · ${health.queued} queued, ${health.running} running`;
  try {
    const [options, inputs] = await Promise.all([apiJson('/v1/bake/options'), apiJson('/v1/inputs')]);
    state.options = options.options;
    await refreshServer();
    buildForm(inputs);
  } catch (e) {
    $('server-status').textContent = 'server: ' + e.message;
    return;
  }
  $('bake-section').hidden = false;
  $('server-section').hidden = false;
  document.body.dataset.ready = 'true';
  clearInterval(state.serverTimer);
  state.serverTimer = setInterval(refreshServer, SERVER_POLL_MS);
}

async function start() {
  $('token-form').addEventListener('submit', useToken);
  $('bake-form').addEventListener('submit', bake);
  $('plan-button').addEventListener('click', dryRun);
  $('preset-draft').addEventListener('click', () => applyPreset('draft'));
  $('preset-production').addEventListener('click', () => applyPreset('production'));
  $('copy-command').addEventListener('click', () => copyText(bakeCommand(bakeOptions())));
  $('copy-job').addEventListener('click', () => copyJob(false));
  $('copy-result-job').addEventListener('click', () => copyJob(true));
  $('copy-result-command').addEventListener('click', () => {
    const job = state.job;
    if (job && job.options) copyText(bakeCommand(job.options));
    else if (job) copyText(`brdfbake run job.json -o out   # job.json: "Copy job JSON" of job ${job.id}`);
  });
  $('cancel-button').addEventListener('click', cancelJob);
  $('download-all').addEventListener('click', () => state.job && download(state.job.id, null));
  try {
    connected(await apiJson('/v1/health'));
  } catch (e) {
    if (e.status === 401) askToken(state.token ? e.message : '');
    else $('server-status').textContent = 'server: ' + e.message;
  }
}

start();
