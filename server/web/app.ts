// The browser page of `vastray serve`: upload, scenes, render, live jobs, result viewer.
// Plain TypeScript over the service's HTTP API (docs/SERVICE.md); compiled by tsc at build
// time, no library. Every /v1 call sends `Authorization: Bearer <token>` once the server has
// asked for one (401); the token lives in sessionStorage for this tab.

interface SceneCamera {
  name: string; index: number; eye: number[]; target: number[]; up: number[]; fov_y_degrees: number;
}
interface Scene {
  id: string; name: string; format: string; upload_bytes: string; package_bytes: string;
  triangles: string; chunks: string; import_job_id: string; cameras?: SceneCamera[];
}
interface Environment {
  id: string; name: string; format: string; upload_bytes: string; width?: number; height?: number;
  device_bytes: string;
}
interface JobStats {
  backend: string; render_seconds: number; rays: string; chunk_loads: string;
  peak_device_bytes: string; memory_budget_bytes: string; passes: string;
}
interface Job {
  id: string; state: string; progress: number; error: string;
  request?: { scene_id: string; width: number; height: number; spp: number; aovs: string[];
              memory_budget_bytes: string; output_format: string };
  import?: { name: string; scene_id: string };
  stats?: JobStats; result_content_type: string;
}
interface JobEvent {
  kind: string; job_id: string; state: string; percent: number; passes_done: string;
  passes_total: string; chunk_loads: string; rays: string; device_bytes: string; error: string;
  time: string;
}

// Job states as the API writes them (vastray.v1.JobState); the page shows them without the prefix.
const kRunning = "JOB_STATE_RUNNING", kSucceeded = "JOB_STATE_SUCCEEDED", kFailed = "JOB_STATE_FAILED";
const kFinal = new Set([kSucceeded, kFailed, "JOB_STATE_CANCELLED"]);
function stateLabel(state: string): string {
  return state.replace(/^JOB_STATE_/, "");
}
const kTokenKey = "vastray.token";

function $(id: string): HTMLElement {
  const element = document.getElementById(id);
  if (!element) throw new Error(`page element #${id} is missing`);
  return element;
}
function input(id: string): HTMLInputElement { return $(id) as HTMLInputElement; }

function formatBytes(bytes: number): string {
  const units = ["B", "KiB", "MiB", "GiB", "TiB"];
  let value = bytes, unit = 0;
  while (value >= 1024 && unit < units.length - 1) { value /= 1024; ++unit; }
  return `${value.toFixed(unit === 0 ? 0 : 1)} ${units[unit]}`;
}
function formatCount(n: number): string { return n.toLocaleString("en-US"); }

// ---- token and API calls ----------------------------------------------------------------

class Unauthorized extends Error {}

let tokenWaiters: Array<() => void> = [];

// Shows the token dialog (once, however many calls wait) and resolves when a token was entered.
function askForToken(wrong: boolean): Promise<void> {
  const dialog = $("token-dialog") as HTMLDialogElement;
  $("token-message").textContent = wrong
    ? "That token was refused by the server (401). Enter the right one."
    : "This server needs its access token (the contents of its --auth-token-file).";
  $("token-message").className = wrong ? "message" : "";
  if (!dialog.open) dialog.showModal();
  input("token-input").focus();
  return new Promise((resolve) => tokenWaiters.push(resolve));
}

function setupTokenDialog(): void {
  $("token-form").addEventListener("submit", () => {
    sessionStorage.setItem(kTokenKey, input("token-input").value.trim());
    input("token-input").value = "";
    const waiters = tokenWaiters;
    tokenWaiters = [];
    waiters.forEach((resolve) => resolve());
  });
  $("token-dialog").addEventListener("cancel", (event) => event.preventDefault());
}

function headers(extra: Record<string, string> = {}): Record<string, string> {
  const token = sessionStorage.getItem(kTokenKey);
  return token ? { ...extra, Authorization: `Bearer ${token}` } : extra;
}

// fetch() with the token; a 401 asks for the token and tries again.
async function api(path: string, init: RequestInit = {}): Promise<Response> {
  for (;;) {
    const sent = sessionStorage.getItem(kTokenKey) !== null;
    const response = await fetch(path, { ...init, headers: headers(init.headers as Record<string, string>) });
    if (response.status !== 401) return response;
    if (sent) sessionStorage.removeItem(kTokenKey);
    await askForToken(sent);
  }
}

async function errorText(response: Response): Promise<string> {
  try {
    const body = await response.json();
    return `${response.status} ${body.error.code}: ${body.error.message}`;
  } catch {
    return `${response.status} ${response.statusText}`;
  }
}

async function apiJson<T>(path: string, init: RequestInit = {}): Promise<T> {
  const response = await api(path, init);
  if (!response.ok) throw new Error(await errorText(response));
  return (await response.json()) as T;
}

// ---- upload ---------------------------------------------------------------------------

// A zip with every file STORED (no compression): enough to carry a model's files in one
// upload, which the server unpacks (docs/SERVICE.md, multi-file models). Names are UTF-8 (flag
// bit 11); no zip64, so together under 4 GiB and 65,535 files.
const crcTable = (() => {
  const table = new Uint32Array(256);
  for (let n = 0; n < 256; ++n) {
    let c = n;
    for (let k = 0; k < 8; ++k) c = c & 1 ? 0xedb88320 ^ (c >>> 1) : c >>> 1;
    table[n] = c >>> 0;
  }
  return table;
})();

function crc32(bytes: Uint8Array): number {
  let crc = 0xffffffff;
  for (let i = 0; i < bytes.length; ++i) crc = crcTable[(crc ^ bytes[i]) & 0xff] ^ (crc >>> 8);
  return (crc ^ 0xffffffff) >>> 0;
}

// A file to upload and its path in the model's folder ("textures/wood.png"; its name alone when
// it was chosen or dropped as a file).
interface ModelFile { path: string; file: File }

async function storedZip(files: ModelFile[]): Promise<Blob> {
  const total = files.reduce((n, { path, file }) => n + file.size + 76 + 2 * path.length * 3, 22);
  if (total > 0xffffffff || files.length > 0xffff)
    throw new Error("too large to zip in the browser (4 GiB or 65,535 files at most): zip the files yourself");
  const parts: BlobPart[] = [], central: BlobPart[] = [];
  let offset = 0;
  for (const { path, file } of files) {
    const data = new Uint8Array(await file.arrayBuffer());
    const name = new TextEncoder().encode(path);
    const crc = crc32(data);
    const local = new DataView(new ArrayBuffer(30));
    local.setUint32(0, 0x04034b50, true); local.setUint16(4, 20, true); local.setUint16(6, 0x0800, true);
    local.setUint32(14, crc, true); local.setUint32(18, data.length, true); local.setUint32(22, data.length, true);
    local.setUint16(26, name.length, true);
    parts.push(local.buffer, name, data);
    const entry = new DataView(new ArrayBuffer(46));
    entry.setUint32(0, 0x02014b50, true); entry.setUint16(4, 20, true); entry.setUint16(6, 20, true);
    entry.setUint16(8, 0x0800, true);
    entry.setUint32(16, crc, true); entry.setUint32(20, data.length, true); entry.setUint32(24, data.length, true);
    entry.setUint16(28, name.length, true); entry.setUint32(42, offset, true);
    central.push(entry.buffer, name);
    offset += 30 + name.length + data.length;
  }
  const centralSize = central.reduce((n, part) => n + (part as ArrayBuffer | Uint8Array).byteLength, 0);
  const end = new DataView(new ArrayBuffer(22));
  end.setUint32(0, 0x06054b50, true); end.setUint16(8, files.length, true); end.setUint16(10, files.length, true);
  end.setUint32(12, centralSize, true); end.setUint32(16, offset, true);
  return new Blob([...parts, ...central, end.buffer], { type: "application/zip" });
}

const kModelExtensions = [".gltf", ".glb", ".obj", ".ply"];

// Uploads one model: a file as it is, several files or a folder (`folder`: its name) as one zip.
async function uploadFiles(files: ModelFile[], folder = ""): Promise<void> {
  if (files.length === 0) return;
  let name = files[0].file.name;
  if (folder !== "") {
    name = folder + ".zip";
  } else if (files.length > 1) {
    const model = files.find((f) => kModelExtensions.some((ext) => f.file.name.toLowerCase().endsWith(ext)));
    name = (model ? model.file.name.replace(/\.[^.]*$/, "") : "model") + ".zip";
  }
  const item = document.createElement("li");
  item.className = "upload";
  item.dataset.name = name;
  $("uploads").prepend(item);
  try {
    const body: Blob = files.length > 1 || folder !== "" ? await storedZip(files) : files[0].file;
    item.textContent = `${name}: uploading ${formatBytes(body.size)}…`;
    const response = await api(`/v1/scenes?name=${encodeURIComponent(name)}&async=true`, { method: "PUT", body });
    if (!response.ok) throw new Error(await errorText(response));
    const scene = (await response.json()) as Scene;
    if (!scene.import_job_id) {
      item.textContent = `${name}: stored (${formatCount(Number(scene.triangles))} triangles)`;
      item.dataset.state = kSucceeded;
      await refreshScenes(scene.id);
      return;
    }
    item.textContent = `${name}: importing (job ${scene.import_job_id})`;
    const final = await watch(scene.import_job_id, (event) => {
      item.dataset.state = event.state;
      const percent = event.state === kRunning ? ` ${event.percent} %` : "";
      item.textContent = `${name}: import ${stateLabel(event.state)}${percent}${event.error ? ": " + event.error : ""}`;
    });
    if (final === kSucceeded) await refreshScenes(scene.id);
  } catch (error) {
    item.dataset.state = kFailed;
    item.textContent = `${name}: ${(error as Error).message}`;
    item.classList.add("message");
  }
}

// Every file below a dropped folder, with its path below that folder (readEntries answers in
// batches until it answers none).
async function folderFiles(folder: FileSystemDirectoryEntry, prefix = ""): Promise<ModelFile[]> {
  const reader = folder.createReader();
  const entries: FileSystemEntry[] = [];
  for (;;) {
    const batch = await new Promise<FileSystemEntry[]>((resolve, reject) => reader.readEntries(resolve, reject));
    if (batch.length === 0) break;
    entries.push(...batch);
  }
  const files: ModelFile[] = [];
  for (const entry of entries) {
    const path = prefix + entry.name;
    if (entry.isDirectory) {
      files.push(...(await folderFiles(entry as FileSystemDirectoryEntry, path + "/")));
    } else if (entry.isFile) {
      const file = await new Promise<File>((resolve, reject) => (entry as FileSystemFileEntry).file(resolve, reject));
      files.push({ path, file });
    }
  }
  return files;
}

// A drop: each dropped folder is one model; the dropped files together are another.
async function dropped(transfer: DataTransfer): Promise<void> {
  const files: ModelFile[] = [];
  const folders: FileSystemDirectoryEntry[] = [];
  for (const item of Array.from(transfer.items)) {
    const entry = item.kind === "file" ? item.webkitGetAsEntry() : null;
    if (entry?.isDirectory) folders.push(entry as FileSystemDirectoryEntry);
    else if (item.kind === "file") { const file = item.getAsFile(); if (file) files.push({ path: file.name, file }); }
  }
  await uploadFiles(files);
  for (const folder of folders) await uploadFiles(await folderFiles(folder), folder.name);
}

function setupUpload(): void {
  const zone = $("drop-zone");
  zone.addEventListener("dragover", (event) => { event.preventDefault(); zone.classList.add("over"); });
  zone.addEventListener("dragleave", () => zone.classList.remove("over"));
  zone.addEventListener("drop", (event) => {
    event.preventDefault();
    zone.classList.remove("over");
    if (event.dataTransfer) void dropped(event.dataTransfer);
  });
  input("file-input").addEventListener("change", () => {
    const files = Array.from(input("file-input").files ?? []).map((file) => ({ path: file.name, file }));
    input("file-input").value = "";
    void uploadFiles(files);
  });
  // A chosen folder: webkitRelativePath is "folder/sub/file"; the zip holds "sub/file".
  input("folder-input").addEventListener("change", () => {
    const chosen = Array.from(input("folder-input").files ?? []);
    input("folder-input").value = "";
    if (chosen.length === 0) return;
    const folder = chosen[0].webkitRelativePath.split("/")[0];
    const files = chosen.map((file) => ({ path: file.webkitRelativePath.split("/").slice(1).join("/"), file }));
    void uploadFiles(files, folder);
  });
}

// ---- scenes ---------------------------------------------------------------------------

const sceneNames = new Map<string, string>();
const sceneCameras = new Map<string, SceneCamera[]>();

async function refreshScenes(select?: string): Promise<void> {
  const scenes: Scene[] = [];
  let token = "";
  do {
    const page = await apiJson<{ scenes?: Scene[]; next_page_token?: string }>(
      `/v1/scenes?page_size=1000${token ? "&page_token=" + encodeURIComponent(token) : ""}`);
    scenes.push(...(page.scenes ?? []));
    token = page.next_page_token ?? "";
  } while (token);
  const body = $("scenes").querySelector("tbody") as HTMLElement;
  const options = $("scene-select") as HTMLSelectElement;
  const previous = select ?? options.value;
  body.replaceChildren();
  options.replaceChildren();
  for (const scene of scenes) {
    sceneNames.set(scene.id, scene.name);
    sceneCameras.set(scene.id, scene.cameras ?? []);
    const row = document.createElement("tr");
    row.dataset.sceneId = scene.id;
    const chunks = Number(scene.chunks);
    for (const [text, numeric] of [[scene.name, false], [formatCount(Number(scene.triangles)), true],
      [chunks > 0 ? formatCount(chunks) : "–", true], [scene.format, false],
      [formatBytes(Number(scene.package_bytes)), true]] as Array<[string, boolean]>) {
      const cell = document.createElement("td");
      cell.textContent = text;
      if (numeric) cell.className = "num";
      row.append(cell);
    }
    const use = document.createElement("button");
    use.type = "button"; use.className = "small"; use.textContent = "render";
    use.addEventListener("click", () => { options.value = scene.id; fillCameraList(); input("width").focus(); });
    const cell = document.createElement("td");
    cell.append(use);
    row.append(cell);
    body.append(row);
    options.append(new Option(`${scene.name} (${scene.id.slice(0, 8)})`, scene.id));
  }
  if (previous && scenes.some((s) => s.id === previous)) options.value = previous;
  $("no-scenes").hidden = scenes.length > 0;
  fillCameraList();
}

// The chosen scene's cameras (Scene.cameras) as options "1: Far", each valued by its index;
// the last option leaves the box as typed. Picking a camera writes what scene_camera takes into
// the box: its name, or its index when the name is empty or another camera has it too.
function fillCameraList(): void {
  const list = $("scene-camera-list") as HTMLSelectElement;
  const cameras = sceneCameras.get(selected("scene-select")) ?? [];
  list.replaceChildren(...cameras.map((c) => new Option(`${c.index ?? 0}: ${c.name || "(no name)"}`,
    String(c.index ?? 0))), new Option(cameras.length ? "another (the box below)" : "none defined (the box below)", ""));
  list.value = "";
}

function pickListedCamera(): void {
  const value = selected("scene-camera-list");
  if (value === "") return;
  const cameras = sceneCameras.get(selected("scene-select")) ?? [];
  const camera = cameras.find((c) => String(c.index ?? 0) === value);
  if (!camera) return;
  const unique = camera.name !== "" && cameras.filter((c) => c.name === camera.name).length === 1;
  input("scene-camera").value = unique ? camera.name : value;
}

// ---- render jobs ----------------------------------------------------------------------

function renderRequest(): object {
  const aovs = Array.from($("aovs").querySelectorAll<HTMLInputElement>("input:checked")).map((box) => box.value);
  return {
    scene_id: ($("scene-select") as HTMLSelectElement).value,
    width: Number(input("width").value), height: Number(input("height").value),
    spp: Number(input("spp").value), max_depth: Number(input("max-depth").value),
    integrator: ($("integrator") as HTMLSelectElement).value,
    texture_lod: selected("texture-lod"),
    memory_budget_bytes: String(Math.round(Number(input("budget").value) * 1048576)),
    aovs, ...lightingRequest(), ...cameraRequest(),
  };
}

function selected(id: string): string { return ($(id) as HTMLSelectElement).value; }

// The numbers in the x, y, z boxes `PREFIX-x`..., empty boxes left out: the server then names
// what is missing ("camera.eye: expected 3 numbers x, y, z, got 2"), and checks the rest.
function vectorOf(prefix: string): number[] {
  return ["x", "y", "z"].map((axis) => input(`${prefix}-${axis}`).value).filter((v) => v !== "").map(Number);
}

// up_axis, sun, no_lights and environment of SubmitJobRequest. "No sun" is the API's sun of intensity 0 (its
// direction, the up axis, is then unused).
function lightingRequest(): object {
  const upAxis = selected("up-axis");
  const request: Record<string, unknown> = { up_axis: upAxis, no_lights: !input("scene-lights").checked };
  const environment = selected("environment-select");
  if (environment !== "") {
    // Empty boxes are left out: the API's scale 1 and rotation 0.
    const map: Record<string, unknown> = { id: environment };
    if (input("environment-scale").value !== "") map.scale = Number(input("environment-scale").value);
    if (input("environment-rotation").value !== "") map.rotation_degrees = Number(input("environment-rotation").value);
    request.environment = map;
  }
  if (selected("sun-mode") === "custom")
    request.sun = { direction: vectorOf("sun"), intensity: Number(input("sun-intensity").value) };
  else if (selected("sun-mode") === "none")
    request.sun = { direction: upAxis === "z" ? [0, 0, 1] : [0, 1, 0], intensity: 0 };
  return request;
}

// scene_camera or camera (the two exclude each other); neither: the scene's first camera, else
// framing. An empty field of view is left out (the API's 0: 45 degrees).
function cameraRequest(): object {
  const mode = selected("camera-mode");
  if (mode === "scene") return { scene_camera: input("scene-camera").value };
  if (mode !== "eye") return {};
  const camera: Record<string, unknown> = { eye: vectorOf("eye"), target: vectorOf("target") };
  const up = vectorOf("camera-up");
  if (up.length > 0) camera.up = up;
  if (input("fov").value !== "") camera.fov_y_degrees = Number(input("fov").value);
  return { camera };
}

// Only the boxes of the chosen sun and camera take input (a disabled fieldset's controls are
// skipped by Tab and by the form's checks); also run at start, since a reload may restore the
// selects.
function syncRenderOptions(): void {
  ($("sun-fields") as HTMLFieldSetElement).disabled = selected("sun-mode") !== "custom";
  input("scene-camera").disabled = selected("camera-mode") !== "scene";
  ($("scene-camera-list") as HTMLSelectElement).disabled = selected("camera-mode") !== "scene";
  ($("camera-fields") as HTMLFieldSetElement).disabled = selected("camera-mode") !== "eye";
  ($("environment-fields") as HTMLFieldSetElement).disabled = selected("environment-select") === "";
}

// The stored environment maps (ListEnvironments) as the options of the environment select, by
// name, size and id; `select` (or the chosen one) stays chosen.
async function refreshEnvironments(select?: string): Promise<void> {
  const environments: Environment[] = [];
  let token = "";
  do {
    const page = await apiJson<{ environments?: Environment[]; next_page_token?: string }>(
      `/v1/environments?page_size=1000${token ? "&page_token=" + encodeURIComponent(token) : ""}`);
    environments.push(...(page.environments ?? []));
    token = page.next_page_token ?? "";
  } while (token);
  const options = $("environment-select") as HTMLSelectElement;
  const previous = select ?? options.value;
  options.replaceChildren(new Option("none (the sky)", ""), ...environments.map((e) =>
    new Option(`${e.name} (${e.width ?? 0}x${e.height ?? 0}, ${e.id.slice(0, 8)})`, e.id)));
  options.value = environments.some((e) => e.id === previous) ? previous : "";
  syncRenderOptions();
}

// An environment map from the file picker: uploaded as it is, then chosen. A refused file shows
// the server's message (it names the file and the limit).
async function uploadEnvironment(): Promise<void> {
  const file = input("environment-file").files?.[0];
  if (!file) return;
  $("environment-message").textContent = `uploading ${file.name}...`;
  try {
    const environment = await apiJson<Environment>(`/v1/environments?name=${encodeURIComponent(file.name)}`,
      { method: "PUT", body: file });
    await refreshEnvironments(environment.id);
    $("environment-message").textContent = `${file.name} stored`;
  } catch (error) {
    $("environment-message").textContent = (error as Error).message;
  }
  input("environment-file").value = "";
}

function setupRenderForm(): void {
  for (const id of ["sun-mode", "camera-mode", "environment-select"]) $(id).addEventListener("change", syncRenderOptions);
  $("environment-file").addEventListener("change", () => void uploadEnvironment());
  $("scene-select").addEventListener("change", fillCameraList);
  $("scene-camera-list").addEventListener("change", pickListedCamera);
  syncRenderOptions();
  // A box the browser refuses (an empty sun intensity) must be visible to say why.
  $("render-form").addEventListener("invalid", () => { ($("light-camera") as HTMLDetailsElement).open = true; }, true);
  $("render-form").addEventListener("submit", async (event) => {
    event.preventDefault();
    $("render-message").textContent = "";
    try {
      const job = await apiJson<Job>("/v1/jobs", {
        method: "POST", body: JSON.stringify(renderRequest()), headers: { "Content-Type": "application/json" } });
      showJob(job);
    } catch (error) {
      $("render-message").textContent = (error as Error).message;
    }
  });
}

interface JobCard { root: HTMLElement; state: HTMLElement; bar: HTMLProgressElement; figures: HTMLElement;
                    cancel: HTMLButtonElement; view: HTMLButtonElement; error: HTMLElement; }
const cards = new Map<string, JobCard>();

function figure(name: string): HTMLElement {
  const span = document.createElement("span");
  span.dataset.figure = name;
  return span;
}

function makeCard(job: Job): JobCard {
  const root = document.createElement("div");
  root.className = "job"; root.id = `job-${job.id}`; root.dataset.jobId = job.id;
  const head = document.createElement("div");
  head.className = "job-head";
  const title = document.createElement("span");
  const r = job.request!;
  title.textContent = `${sceneNames.get(r.scene_id) ?? r.scene_id.slice(0, 8)} · ${r.width}×${r.height} · ${r.spp} spp`;
  const state = document.createElement("span");
  const cancel = document.createElement("button");
  cancel.type = "button"; cancel.className = "small cancel"; cancel.textContent = "cancel";
  cancel.addEventListener("click", () => void cancelJob(job.id));
  const view = document.createElement("button");
  view.type = "button"; view.className = "small view"; view.textContent = "view"; view.hidden = true;
  view.addEventListener("click", () => void openViewer(job.id));
  head.append(title, state, cancel, view);
  const bar = document.createElement("progress");
  bar.max = 100; bar.value = 0;
  const figures = document.createElement("div");
  figures.className = "figures";
  for (const name of ["passes", "chunks", "rays", "memory", "backend"]) figures.append(figure(name));
  const error = document.createElement("div");
  error.className = "message job-error";
  root.append(head, bar, figures, error);
  $("jobs").prepend(root);
  return { root, state, bar, figures, cancel, view, error };
}

function setFigure(card: JobCard, name: string, text: string): void {
  (card.figures.querySelector(`[data-figure="${name}"]`) as HTMLElement).textContent = text;
}

function updateState(card: JobCard, state: string, percent: number, error: string): void {
  card.root.dataset.state = state;
  card.state.textContent = stateLabel(state);
  card.state.className = `state state-${stateLabel(state)}`;
  card.bar.value = percent;
  card.cancel.hidden = kFinal.has(state);
  card.view.hidden = state !== kSucceeded;
  card.error.textContent = error;
}

// Device memory against the budget, as the card shows it.
function memoryText(device: number, budget: number): string {
  return `device ${formatBytes(device)} of ${formatBytes(budget)}` +
    (budget > 0 ? ` (${((100 * device) / budget).toFixed(1)} %)` : "");
}

// Figures a finished job's stats give (rays per second over the render's own time).
function showStats(card: JobCard, job: Job): void {
  const s = job.stats;
  const budget = Number(job.request?.memory_budget_bytes ?? 0);
  if (!s || !s.backend) {
    setFigure(card, "memory", budget ? `budget ${formatBytes(budget)}` : "");
    return;
  }
  const rays = Number(s.rays);
  setFigure(card, "rays", s.render_seconds > 0 ? `${formatCount(Math.round(rays / s.render_seconds))} rays/s` : "");
  const peak = Number(s.peak_device_bytes), ranBudget = Number(s.memory_budget_bytes) || budget;
  setFigure(card, "memory", memoryText(peak, ranBudget));
  setFigure(card, "backend", s.backend);
  setFigure(card, "chunks", `${formatCount(Number(s.chunk_loads))} chunk loads`);
}

function showJob(job: Job): void {
  if (!job.request || cards.has(job.id)) return;
  const card = makeCard(job);
  cards.set(job.id, card);
  updateState(card, job.state, job.progress, job.error);
  showStats(card, job);
  if (!kFinal.has(job.state)) void followJob(job);
}

async function followJob(job: Job): Promise<void> {
  const id = job.id;
  const card = cards.get(id)!;
  const budget = Number(job.request?.memory_budget_bytes ?? 0);
  // Rays per second while running: the rays counted between the first RUNNING event this
  // watch saw and the latest, over the time between their timestamps.
  let first: { rays: number; time: number } | undefined;
  try {
    await watch(id, (event) => {
      updateState(card, event.state, event.percent, event.error);
      if (Number(event.passes_total) > 0)
        setFigure(card, "passes", `pass ${event.passes_done} of ${event.passes_total}`);
      setFigure(card, "chunks", `${formatCount(Number(event.chunk_loads ?? 0))} chunk loads`);
      const device = Number(event.device_bytes ?? 0);
      if (device > 0) setFigure(card, "memory", memoryText(device, budget));
      if (event.state !== kRunning) return;
      const rays = Number(event.rays ?? 0), time = Date.parse(event.time);
      if (!first) first = { rays, time };
      else if (rays > first.rays && time > first.time)
        setFigure(card, "rays", `${formatCount(Math.round((rays - first.rays) / ((time - first.time) / 1000)))} rays/s`);
    });
    // The stream has ended: the card takes the job as stored, whatever the last event said.
    const ended = await apiJson<Job>(`/v1/jobs/${id}`);
    updateState(card, ended.state, ended.progress, ended.error);
    showStats(card, ended);
  } catch (error) {
    card.error.textContent = (error as Error).message;
  }
}

async function cancelJob(id: string): Promise<void> {
  const card = cards.get(id)!;
  try {
    const job = await apiJson<Job>(`/v1/jobs/${id}:cancel`, {
      method: "POST", body: JSON.stringify({ reason: "cancelled from the web page" }),
      headers: { "Content-Type": "application/json" } });
    updateState(card, job.state, job.progress, job.error);
  } catch (error) {
    card.error.textContent = (error as Error).message;
  }
}

// Events received, for the browser test's figures (tests/server/web_page_test.py).
const pageCounters = { events: 0 };
(window as unknown as { vastrayPage: object }).vastrayPage = pageCounters;

// Server-Sent Events through fetch (EventSource cannot send the Authorization header): calls
// `onEvent` for each JobEvent and resolves with the final state.

async function watch(id: string, onEvent: (event: JobEvent) => void): Promise<string> {
  const response = await api(`/v1/jobs/${id}/events`, { headers: { Accept: "text/event-stream" } });
  if (!response.ok || !response.body) throw new Error(await errorText(response));
  const reader = response.body.pipeThrough(new TextDecoderStream()).getReader();
  let buffer = "", state = "";
  for (;;) {
    const { value, done } = await reader.read();
    if (done) break;
    buffer += value;
    let end: number;
    while ((end = buffer.indexOf("\n\n")) >= 0) {
      const block = buffer.slice(0, end);
      buffer = buffer.slice(end + 2);
      const kind = /^event: (.*)$/m.exec(block)?.[1] ?? "";
      const data = /^data: (.*)$/m.exec(block)?.[1] ?? "{}";
      if (kind === "error") throw new Error(JSON.parse(data).message);
      const event = JSON.parse(data) as JobEvent;
      ++pageCounters.events;
      state = event.state;
      onEvent(event);
    }
  }
  return state;
}

async function loadJobs(): Promise<void> {
  const page = await apiJson<{ jobs?: Job[] }>("/v1/jobs?page_size=20");
  for (const job of (page.jobs ?? []).reverse()) showJob(job);
}

// ---- result viewer --------------------------------------------------------------------

let viewerUrl = "";

async function showPreview(id: string, aov: string): Promise<void> {
  for (const button of $("aov-switcher").querySelectorAll("button"))
    button.setAttribute("aria-selected", String(button.dataset.aov === aov));
  $("viewer-message").textContent = "";
  const response = await api(`/v1/jobs/${id}/result?aov=${aov}&format=png`);
  if (!response.ok) {
    $("viewer-message").textContent = await errorText(response);
    return;
  }
  const image = $("result-image") as HTMLImageElement;
  if (viewerUrl) URL.revokeObjectURL(viewerUrl);
  viewerUrl = URL.createObjectURL(await response.blob());
  image.dataset.aov = "";
  image.onload = () => { image.dataset.aov = aov; };
  image.src = viewerUrl;
}

async function openViewer(id: string): Promise<void> {
  const job = await apiJson<Job>(`/v1/jobs/${id}`);
  $("viewer-section").hidden = false;
  $("viewer-job").textContent = id;
  const switcher = $("aov-switcher");
  switcher.replaceChildren();
  const names = ["beauty", ...(job.request?.aovs ?? [])];
  const order = ["beauty", "depth", "normal", "albedo", "chunkid", "cost", "primid"];
  for (const aov of order.filter((name) => names.includes(name))) {
    const button = document.createElement("button");
    button.type = "button"; button.textContent = aov; button.dataset.aov = aov;
    button.setAttribute("role", "tab");
    button.addEventListener("click", () => void showPreview(id, aov));
    switcher.append(button);
  }
  const download = $("download") as HTMLAnchorElement;
  download.onclick = async (event) => {
    event.preventDefault();
    const response = await api(`/v1/jobs/${id}/result`);
    if (!response.ok) { $("viewer-message").textContent = await errorText(response); return; }
    const link = document.createElement("a");
    link.href = URL.createObjectURL(await response.blob());
    link.download = `${id}.${job.result_content_type === "image/x-exr" ? "exr" : "png"}`;
    link.click();
    setTimeout(() => URL.revokeObjectURL(link.href), 10000);
  };
  await showPreview(id, "beauty");
}

// ---- start ----------------------------------------------------------------------------

async function start(): Promise<void> {
  setupTokenDialog();
  setupUpload();
  setupRenderForm();
  $("refresh-scenes").addEventListener("click", () => void refreshScenes().then(() => refreshEnvironments()));
  try {
    await refreshScenes();
    await refreshEnvironments();
    await loadJobs();
    $("server-status").textContent = "connected";
    document.body.dataset.ready = "true";
  } catch (error) {
    $("server-status").textContent = (error as Error).message;
  }
}

void start();
