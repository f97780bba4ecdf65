// <oer-viewer>: a product under an environment's lights, rendered by oer-server, as one custom
// element (one script tag, as model-viewer does). Frames come from GET /v1/render
// (api/openapi.yaml); the view state lives in the element's attributes (web/README.md).

// While the pointer drags or a control slides, frames are cheaper: the preview recipe of
// GET /v1/render (api/openapi.yaml): one sample, half the size, JPEG quality 50, and hard
// shadows from 256-texel maps, which keep a turning environment's new shadow maps cheap (their
// ground-visibility bakes cost 14 ms a preview against 35 ms at 512, browser_benchmark.mjs).
const PREVIEW = { scale: 0.5, samples: 1, quality: 50, shadow_resolution: 256, shadow_filter: 'hard' };
// Once the change rests, the frame comes in two stages: 'sharp', the full frame at one sample
// (a third of its time on llvmpipe: no supersampling), then at once 'full', with the server's
// default anti-aliasing. The framing of all three stages is the same (it depends on the aspect
// ratio alone).
const SHARP = { samples: 1 };
// The largest frame side GET /v1/render accepts.
const MAX_FRAME_SIDE = 4096;
// A preliminary frame (drawn while its scene's occlusion transfer is baked) is asked for again
// this often until the whole one comes.
const PRELIMINARY_RETRY_MS = 500;
// The query parameters that decide a scene's occlusion transfer (the server bakes one per
// scene: its meshes, the ground and the bounce; a colour reuses it).
const TRANSFER_PARAMETERS = ['mesh', 'ground', 'occlusion', 'bounce'];
// A frame longer in coming than this shows the waiting bar (and aria-busy), so that no wait
// longer than half a second is silent.
const WAITING_MS = 500;
// The shadow-only floor is the opaque one's scene (ground=shadow shares its transfer).
const transferKey = (url) => {
  const query = new URL(url, location.href).searchParams;
  if (query.get('ground') === 'shadow') {
    query.set('ground', 'on');
  }
  return TRANSFER_PARAMETERS.map((name) => `${name}=${query.getAll(name).join('+')}`).join('&');
};
// The orbit when camera-orbit gives none: GET /v1/render's defaults for yaw, pitch, distance.
const DEFAULT_ORBIT = { yaw: 30, pitch: 15, distance: 3 };
// Orbit limits: from just below the horizon (with a floor, opaque or shadow-only, from the
// horizon: the server raises an orbit whose eye would see the floor's underside, and the drag
// stops where it does) to just short of straight down (the up vector degenerates at 90
// degrees), and zoom within a factor of about 15 either way.
const PITCH_LIMITS = [-10, 89];
const PITCH_LIMITS_OVER_FLOOR = [0, 89];
const DISTANCE_LIMITS = [0.2, 50];
const DEGREES_PER_PIXEL = 0.4;
const KEY_STEP_DEGREES = 5;
const WHEEL_ZOOM_PER_PIXEL = 0.0015;
// The turntable (auto-rotate): degrees of yaw per second, and how long a drag, the wheel or a
// key holds it still after the shopper lets go (model-viewer's rotation-per-second and
// auto-rotate-delay play the same parts).
const TURNTABLE_DEGREES_PER_SECOND = 30;
const TURNTABLE_DELAY_MILLISECONDS = 3000;
// How long the pointer must rest (no movement, no wheel) before the full frame is asked for.
const REST_MILLISECONDS = 250;

const clamp = (value, [low, high]) => Math.min(high, Math.max(low, value));
// Angles kept in (-180, 180], the range GET /v1/render's yaw accepts with room to spare.
const wrapDegrees = (angle) => ((((angle + 180) % 360) + 360) % 360) - 180;
const rounded = (value) => Math.round(value * 100) / 100;

// Where direction [x, y, z] (world space, unturned map) lands on an equirectangular image, as
// fractions of its width and height (docs/design.md section 3: theta from +Y, phi = atan2(z, x);
// u = (phi + pi) / 2 pi, v = theta / pi).
export function equirectangularUv([x, y, z]) {
  const length = Math.hypot(x, y, z) || 1;
  return {
    u: (Math.atan2(z, x) + Math.PI) / (2 * Math.PI),
    v: Math.acos(clamp(y / length, [-1, 1])) / Math.PI,
  };
}

// Linear RGB in [0, 1] from '#rrggbb' (sRGB, as a shop names a color), by the sRGB transfer
// function (IEC 61966-2-1); null for anything else.
export function linearFromHex(text) {
  const match = /^#([0-9a-f]{6})$/i.exec(text?.trim() ?? '');
  if (!match) {
    return null;
  }
  return [0, 2, 4].map((offset) => {
    const encoded = parseInt(match[1].slice(offset, offset + 2), 16) / 255;
    return encoded <= 0.04045 ? encoded / 12.92 : ((encoded + 0.055) / 1.055) ** 2.4;
  });
}

// Before the first frame the element is never an empty box: a placeholder (a soft gradient, the
// poster over it) with a loading indicator; without a `poster` attribute the poster is a small
// frame of the same view (the preview recipe at this fraction of the CSS size: about 50 ms on
// llvmpipe against 250 ms for the sharp frame, and cached by the browser and the server alike).
// A hotspot's name as the server takes it (api/openapi.yaml, HotspotName): its slot is
// `hotspot-NAME`.
const HOTSPOT_SLOT = /^hotspot-([A-Za-z0-9_-]{1,64})$/;
const HOTSPOT_ATTRIBUTES = ['slot', 'data-position', 'data-normal', 'data-surface'];

const POSTER_SCALE = 0.2;
// Without a size from the page, the element is as wide as its container (or 300 px where it
// shrinks to fit, as <canvas> does) at this aspect ratio; a page's width or height overrides it.
const DEFAULT_ASPECT_RATIO = '4 / 3';
const DEFAULT_WIDTH_PX = 300;

const STYLE = `
  :host { display: block; position: relative; overflow: hidden; touch-action: none;
          aspect-ratio: ${DEFAULT_ASPECT_RATIO}; cursor: grab; outline: none; }
  :host(:focus-visible) { box-shadow: inset 0 0 0 3px #4d90fe; }
  :host([dragging]) { cursor: grabbing; }
  /* In flow, no height: gives the element a width where it would shrink to its content. */
  .sizer { width: ${DEFAULT_WIDTH_PX}px; max-width: 100%; height: 0; }
  /* Every layer is out of flow, so that none stretches an element sized by its aspect ratio. */
  .frame, .placeholder, .poster, .message { position: absolute; inset: 0; }
  .frame { display: block; width: 100%; height: 100%; user-select: none;
           -webkit-user-drag: none; pointer-events: none; }
  .frame:not([src]) { visibility: hidden; }
  .placeholder { background: radial-gradient(circle at 50% 40%, #7a7a7a, #3a3a3a);
                 pointer-events: none; }
  :host([loaded]) .placeholder { display: none; }
  .poster { width: 100%; height: 100%; object-fit: cover; }
  .poster:not([src]), .poster.broken { visibility: hidden; }
  .loading { position: absolute; left: 50%; top: 50%; transform: translate(-50%, -50%);
             display: flex; align-items: center; gap: 0.6em; padding: 0.5em 0.9em;
             border-radius: 999px; background: rgb(0 0 0 / 0.6); color: #fff;
             font: 14px/1.3 system-ui, sans-serif; white-space: nowrap; }
  .spinner { width: 1em; height: 1em; border-radius: 50%; border: 2px solid rgb(255 255 255 / 0.35);
             border-top-color: #fff; animation: spin 0.9s linear infinite; }
  @keyframes spin { to { transform: rotate(360deg); } }
  :host([failed]) .loading { display: none; }
  .waiting { display: none; position: absolute; left: 0; top: 0; height: 4px; width: 30%;
             background: #4d90fe; animation: waiting 1.2s ease-in-out infinite; }
  :host([waiting]) .waiting { display: block; }
  @keyframes waiting { from { left: -30%; } to { left: 100%; } }
  /* A failure, in words, over whatever is shown: never a silent black or empty box. */
  .message { display: none; margin: auto; width: fit-content; max-width: calc(100% - 2em);
             height: fit-content; max-height: calc(100% - 2em); overflow: auto; padding: 0.8em 1em;
             border-radius: 6px; background: rgb(20 20 20 / 0.88); color: #fff;
             border-left: 4px solid #ff8a80; font: 14px/1.4 system-ui, sans-serif;
             cursor: default; }
  :host([failed]) .message { display: block; }
  .message strong { display: block; font-size: 15px; margin-bottom: 0.25em; }
  .message p { margin: 0; overflow-wrap: anywhere; }
  /* Slotted hotspots (<button slot="hotspot-NAME" data-position=... data-normal=...>), each
     centred on its point; hidden while the product hides it or before its first placement. */
  .hotspots { position: absolute; inset: 0; pointer-events: none; }
  .hotspot { position: absolute; left: 0; top: 0; pointer-events: auto; }
  .hotspot[hidden] { display: none; }
  @media (prefers-reduced-motion: reduce) {
    .waiting { width: 100%; animation: none; opacity: 0.6; }
    .spinner { animation: none; border-top-color: rgb(255 255 255 / 0.35); }
  }
`;

export class OerViewer extends HTMLElement {
  static observedAttributes = [
    'server', 'mesh', 'environment', 'lights', 'camera-orbit', 'camera-target', 'camera-asset',
    'exposure', 'background', 'ground', 'shadows', 'shadow-intensity', 'shadow-softness',
    'environment-yaw', 'base-color', 'base-color-material', 'variant', 'auto-rotate', 'poster',
  ];

  #image;
  #poster;
  #posterController = null;  // the server's small poster frame, in flight
  #posterObjectUrl = null;
  #messageHeadline;
  #messageText;
  #failures = 0;  // counts failures and shown frames, so that a late explanation shows only if still true
  #showingPreliminary = false;
  #controller = null;  // the one request in flight
  // The scenes (transferKey) whose whole frame came: a frame of any other asks with
  // `Prefer: wait=1` (RFC 7240), so that while its transfer is baked the server answers at once
  // with a preliminary frame (X-Oer-Preliminary), shown, then asked for again. Only then: the
  // header makes a cross-origin request need a CORS preflight.
  #refinedScenes = new Set();
  #objectUrl = null;
  #lights = [];
  #lightsFor = null;  // the environment URL #lights came from
  #drag = null;
  #pointers = new Map();  // the pointers down on the element, by id: their latest positions
  #pinch = null;  // two pointers down: the span between them and the distance at its start
  #turntable = { frame: 0, last: 0, heldUntil: 0 };
  #shownDistance = null;  // the shown orbit's distance, from its frame's X-Oer-Camera
  #dragging = false;
  #previewing = false;  // previews are being asked for, until the change rests
  #settingState = false;  // an attribute is being set by an interaction that asks for its own frames
  #restTimer = 0;
  #pendingPreview = false;
  #resizeObserver;
  #connected = false;
  #hotspotLayer;
  #hotspotWrappers = new Map();  // hotspot name -> its positioned wrapper holding its slot
  #hotspotObserver;
  #placementController = null;  // the hotspots' placement in flight apart from a frame's
  #shownUrl = null;  // the URL of the frame shown

  constructor() {
    super();
    const root = this.attachShadow({ mode: 'open' });
    const style = document.createElement('style');
    style.textContent = STYLE;
    const sizer = document.createElement('div');
    sizer.className = 'sizer';
    this.#image = document.createElement('img');
    this.#image.alt = '';
    this.#image.className = 'frame';
    this.#image.part = 'frame';
    // Until the first frame: the poster and a loading indicator over a soft gradient.
    const placeholder = document.createElement('div');
    placeholder.className = 'placeholder';
    placeholder.part = 'placeholder';
    this.#poster = document.createElement('img');
    this.#poster.alt = '';
    this.#poster.className = 'poster';
    this.#poster.part = 'poster';
    this.#poster.addEventListener('error', () => this.#poster.classList.add('broken'));
    this.#poster.addEventListener('load', () => this.#poster.classList.remove('broken'));
    const loading = document.createElement('div');
    loading.className = 'loading';
    loading.part = 'loading';
    const spinner = document.createElement('span');
    spinner.className = 'spinner';
    loading.append(spinner, 'Loading 3D view…');
    placeholder.append(this.#poster, loading);
    const waitingBar = document.createElement('div');
    waitingBar.className = 'waiting';
    waitingBar.part = 'waiting';
    // A failure in plain words (the error event's `message`), over the view.
    const message = document.createElement('div');
    message.className = 'message';
    message.part = 'message';
    this.#messageHeadline = document.createElement('strong');
    this.#messageText = document.createElement('p');
    message.append(this.#messageHeadline, this.#messageText);
    this.#hotspotLayer = document.createElement('div');
    this.#hotspotLayer.className = 'hotspots';
    this.#hotspotLayer.part = 'hotspots';
    root.append(style, sizer, this.#image, this.#hotspotLayer, placeholder, waitingBar, message);
    this.#hotspotObserver = new MutationObserver(() => this.#syncHotspots());
    this.#resizeObserver = new ResizeObserver(() => this.#requestFrame('sharp'));
    // Here rather than on connection, so that moving the element does not add them twice.
    this.addEventListener('pointerdown', this.#onPointerDown);
    this.addEventListener('pointermove', this.#onPointerMove);
    this.addEventListener('pointerup', this.#onPointerUp);
    this.addEventListener('pointercancel', this.#onPointerUp);
    this.addEventListener('wheel', this.#onWheel, { passive: false });
    this.addEventListener('keydown', this.#onKeyDown);
  }

  connectedCallback() {
    this.#connected = true;
    if (!this.hasAttribute('tabindex')) {
      this.tabIndex = 0;
    }
    if (!this.hasAttribute('role')) {
      this.setAttribute('role', 'img');
    }
    this.#showPoster();
    this.#setWaiting(this.hasAttribute('waiting'));
    this.#resizeObserver.observe(this);
    this.#hotspotObserver.observe(this, {
      childList: true, subtree: true, attributes: true, attributeFilter: HOTSPOT_ATTRIBUTES,
    });
    this.#syncHotspots();
    this.#loadLights();
    this.#updateTurntable();
  }

  disconnectedCallback() {
    this.#connected = false;
    this.#resizeObserver.disconnect();
    this.#hotspotObserver.disconnect();
    this.#placementController?.abort();
    this.#controller?.abort();
    this.#controller = null;
    this.#posterController?.abort();
    this.#posterController = null;
    clearTimeout(this.#restTimer);
    this.#updateTurntable();
  }

  attributeChangedCallback(name, oldValue, newValue) {
    if (!this.#connected || oldValue === newValue) {
      return;
    }
    if (name === 'server' || name === 'environment') {
      this.#loadLights();
    }
    if (name === 'lights') {
      this.#dispatchLightsChange();
    }
    if (name === 'auto-rotate') {
      this.#updateTurntable();
      return;
    }
    if (name === 'poster') {
      this.#showPoster();
      return;
    }
    // A drag, the wheel, a key or adjust() asks for its own frames; the attribute only records
    // the state.
    if (!this.#settingState) {
      this.#requestFrame('sharp');
    }
  }

  // The server's base URL ('' = this page's origin).
  get server() { return (this.getAttribute('server') ?? '').replace(/\/+$/, ''); }
  get environment() { return this.getAttribute('environment') || 'default'; }
  get mesh() { return this.getAttribute('mesh') || 'default'; }
  // The equirectangular preview of the environment (GET /v1/environments/{id}/preview.jpg).
  get environmentPreviewUrl() {
    return `${this.server}/v1/environments/${encodeURIComponent(this.environment)}/preview.jpg`;
  }

  // {yaw, pitch, distance} from camera-orbit="yaw pitch [distance]"; null when absent (the
  // server frames the scene itself).
  get orbit() {
    const text = this.getAttribute('camera-orbit');
    if (!text) {
      return null;
    }
    const [yaw, pitch, distance] = text.trim().split(/[\s,]+/).map(Number);
    return {
      yaw: Number.isFinite(yaw) ? yaw : DEFAULT_ORBIT.yaw,
      pitch: Number.isFinite(pitch) ? pitch : DEFAULT_ORBIT.pitch,
      distance: Number.isFinite(distance) ? distance : null,
    };
  }

  set orbit({ yaw, pitch, distance }) {
    const limits = this.getAttribute('ground') === 'off' ? PITCH_LIMITS : PITCH_LIMITS_OVER_FLOOR;
    const parts = [rounded(wrapDegrees(yaw)), rounded(clamp(pitch, limits))];
    if (distance != null) {
      parts.push(rounded(clamp(distance, DISTANCE_LIMITS)));
    }
    this.setAttribute('camera-orbit', parts.join(' '));
  }

  // Every light of the environment (the `lights` of GET /v1/environments/{id}: direction,
  // intensity, luminance_share, ...), each with its index and its weight from the lights
  // attribute (1 when absent).
  get lights() {
    const weights = this.#weights();
    return this.#lights.map((light, index) => ({ ...light, index, weight: weights[index] ?? 1 }));
  }

  // Sets light `index` to `weight`: 0 switches it off, 1 is the environment's own, up to 4
  // (GET /v1/render's range for each of `lights`). adjusting: as one step of a continuous
  // change (a dimmer sliding), as adjust() does.
  setLight(index, weight, { adjusting = false } = {}) {
    const weights = this.#lights.map((_, i) => this.#weights()[i] ?? 1);
    weights[index] = weight;
    if (adjusting) {
      this.adjust('lights', weights.join(','));
    } else {
      this.setAttribute('lights', weights.join(','));
    }
  }

  // Sets attribute `name` to `value` (null removes it) as one step of a continuous change, a
  // slider being dragged say: previews while the steps keep coming, the full frame once they
  // rest.
  adjust(name, value) {
    this.#setState(() => {
      if (value === null || value === undefined) {
        this.removeAttribute(name);
      } else {
        this.setAttribute(name, String(value));
      }
    });
    this.#preview();
  }

  // Back to the server's own framing.
  resetView() {
    this.removeAttribute('camera-asset');
    this.removeAttribute('camera-orbit');
    this.removeAttribute('camera-target');
  }

  // The GET /v1/render URL of the frame this element shows, at stage 'preview' (the cheap
  // one), 'sharp' (full size, one sample) or 'full'.
  frameUrl(stage = 'full') {
    if (!['preview', 'sharp', 'full'].includes(stage)) {
      throw new RangeError(`frameUrl: stage is 'preview', 'sharp' or 'full', not '${stage}'`);
    }
    return this.#urlFor(stage);
  }

  // The frame this element shows (frameUrl('full')) as a RenderRequest: the JSON body of
  // POST /v1/render, and of a batch job's frames (POST /v1/jobs), which then draw that frame.
  // assetCamera: false puts the orbit the view returns to when it turns (camera-orbit, else the
  // server's framing) in place of one of the product's own cameras: a turntable turns an orbit.
  renderRequest({ assetCamera = true } = {}) {
    return renderRequestOf(new URL(this.#urlFor('full', { assetCamera }), location.href).searchParams);
  }

  // frameUrl's, and also for stage 'poster': the preview recipe at POSTER_SCALE of the CSS size
  // (whatever devicePixelRatio: it is shown blurred, for a moment).
  #urlFor(stage, { assetCamera = true } = {}) {
    const preview = stage === 'preview' || stage === 'poster';
    const rect = this.getBoundingClientRect();
    const ratio = stage === 'poster' ? 1 : window.devicePixelRatio || 1;
    const scale = { preview: PREVIEW.scale, poster: POSTER_SCALE }[stage] ?? 1;
    const side = (css) =>
      Math.max(1, Math.round(Math.min(MAX_FRAME_SIDE, Math.max(1, css) * ratio) * scale));
    const query = new URLSearchParams();
    query.set('environment', this.environment);
    for (const mesh of this.mesh.split(/\s+/).filter(Boolean)) {
      query.append('mesh', mesh);
    }
    query.set('width', side(rect.width));
    query.set('height', side(rect.height));
    // One of the asset's own cameras (the mesh's `cameras`) replaces the orbit, which is kept
    // for when the view turns again.
    const asset = assetCamera ? this.getAttribute('camera-asset') : null;
    const orbit = asset ? null : this.orbit;
    if (asset) {
      query.set('camera', `asset:${asset.trim()}`);
    }
    if (orbit) {
      query.set('yaw', orbit.yaw);
      query.set('pitch', orbit.pitch);
      if (orbit.distance != null) {
        query.set('distance', orbit.distance);
      }
    }
    const target = this.getAttribute('camera-target');
    if (target && !asset) {
      query.set('target', target.trim().split(/[\s,]+/).join(','));
    }
    // base-color: '#rrggbb' (sRGB) or the API's linear 'r,g,b', which the server validates.
    const baseColorText = this.getAttribute('base-color');
    if (baseColorText) {
      const linear = linearFromHex(baseColorText);
      query.set('base_color',
                linear ? linear.map((value) => value.toFixed(4)).join(',') : baseColorText.replace(/\s+/g, ''));
      // base-color-material: the one material (by name) the colour goes to, else every one.
      const material = this.getAttribute('base-color-material');
      if (material) {
        query.set('base_color_material', material);
      }
    }
    // variant: one of the product's own variants (KHR_materials_variants), by name.
    const variant = this.getAttribute('variant');
    if (variant) {
      query.set('variant', variant);
    }
    for (const [attribute, parameter] of [['lights', 'lights'], ['exposure', 'exposure'],
                                          ['background', 'background'], ['ground', 'ground'], ['shadows', 'shadows'],
                                          ['shadow-intensity', 'shadow_intensity'],
                                          ['shadow-softness', 'shadow_softness'],
                                          ['environment-yaw', 'environment_yaw']]) {
      const value = this.getAttribute(attribute);
      if (value) {
        query.set(parameter, value.replace(/\s+/g, ''));
      }
    }
    // JPEG has no alpha: a transparent background needs PNG for the page to show through.
    if (this.getAttribute('background') === 'transparent') {
      query.set('format', 'png');
    }
    if (preview) {
      for (const parameter of ['samples', 'quality', 'shadow_resolution', 'shadow_filter']) {
        query.set(parameter, PREVIEW[parameter]);
      }
    } else if (stage === 'sharp') {
      query.set('samples', SHARP.samples);
    }
    return `${this.server}/v1/render?${query}`;
  }

  // The frame this element shows at full quality, as a PNG Blob: the same request with
  // format=png and samples=4 (GET /v1/render's default anti-aliasing, also for a preview).
  async snapshot() {
    const url = new URL(this.frameUrl('full'), location.href);
    url.searchParams.set('format', 'png');
    url.searchParams.set('samples', '4');
    url.searchParams.delete('quality');
    const response = await fetch(url);
    if (!response.ok) {
      throw await problemOf(response, url.href);
    }
    return response.blob();
  }

  // The surface of the product at a point of the element (clientX, clientY: a pointer
  // event's), as GET /v1/pick names it for the full frame's camera: a Promise of
  // { object, primitive, triangle, barycentric, position, normal, surface } (`surface` the
  // data-surface text that places a hotspot there), or of null where no product is seen. It
  // rejects with the server's problem.
  async pick(clientX, clientY) {
    const rect = this.getBoundingClientRect();
    const url = new URL(this.frameUrl('full'), location.href);
    const width = Number(url.searchParams.get('width'));
    const height = Number(url.searchParams.get('height'));
    const x = ((clientX - rect.left) / rect.width) * width;
    const y = ((clientY - rect.top) / rect.height) * height;
    if (!(x >= 0 && x < width && y >= 0 && y < height)) {
      return null;
    }
    url.pathname = url.pathname.replace(/\/v1\/render$/, '/v1/pick');
    url.searchParams.set('pixel', `${x},${y}`);
    const response = await fetch(url);
    if (!response.ok) {
      throw await problemOf(response, url.href);
    }
    const picked = await response.json();
    if (!picked.hit) {
      return null;
    }
    const surface = [picked.object, picked.primitive, picked.triangle, ...picked.barycentric].join(' ');
    return { ...picked, surface };
  }

  // The slotted hotspots: children whose slot is `hotspot-NAME`, each with data-surface
  // ("OBJECT PRIMITIVE TRIANGLE A B C": a point of a triangle, as pick() names it) or
  // data-position and data-normal ("x y z" each, world space), as the `hotspot` parameters of
  // GET /v1/hotspots. Children whose point is missing or malformed are left hidden.
  #hotspotParameters() {
    const numbers = (text, count) => {
      const values = (text ?? '').trim().split(/[\s,]+/).map(Number);
      return values.length === count && values.every(Number.isFinite) ? values.join(',') : null;
    };
    const parameters = new Map();
    for (const child of this.children) {
      const name = HOTSPOT_SLOT.exec(child.slot)?.[1];
      if (!name) {
        continue;
      }
      const surface = numbers(child.dataset.surface, 6);
      const position = numbers(child.dataset.position, 3);
      const normal = numbers(child.dataset.normal, 3);
      if (surface) {
        parameters.set(name, `${name}:surface:${surface}`);
      } else if (position && normal) {
        parameters.set(name, `${name}:point:${position},${normal}`);
      }
    }
    return parameters;
  }

  // One positioned wrapper with a named slot per slotted hotspot (a slot must exist for a
  // child to show), then their placement in the shown frame.
  #syncHotspots() {
    const names = new Set();
    for (const child of this.children) {
      const name = HOTSPOT_SLOT.exec(child.slot)?.[1];
      if (name) {
        names.add(name);
      }
    }
    for (const [name, wrapper] of this.#hotspotWrappers) {
      if (!names.has(name)) {
        wrapper.remove();
        this.#hotspotWrappers.delete(name);
      }
    }
    for (const name of names) {
      if (!this.#hotspotWrappers.has(name)) {
        const wrapper = document.createElement('div');
        wrapper.className = 'hotspot';
        wrapper.hidden = true;
        const slot = document.createElement('slot');
        slot.name = `hotspot-${name}`;
        wrapper.append(slot);
        this.#hotspotLayer.append(wrapper);
        this.#hotspotWrappers.set(name, wrapper);
      }
    }
    if (this.#shownUrl) {
      this.#placementController?.abort();
      const controller = new AbortController();
      this.#placementController = controller;
      this.#placements(this.#shownUrl, controller.signal).then((placed) => {
        if (controller === this.#placementController) {
          this.#placementController = null;
          this.#applyPlacements(placed);
        }
      });
    }
  }

  // Where the frame of `frameUrl` shows each slotted hotspot (GET /v1/hotspots with the
  // frame's own parameters), or null without hotspots or when the placement failed (the
  // hotspots are then hidden: a hotspot shown where the product may hide it is worse).
  async #placements(frameUrl, signal) {
    const parameters = this.#hotspotParameters();
    if (parameters.size === 0) {
      return { url: frameUrl, answer: null };
    }
    const url = new URL(frameUrl, location.href);
    url.pathname = url.pathname.replace(/\/v1\/render$/, '/v1/hotspots');
    for (const parameter of parameters.values()) {
      url.searchParams.append('hotspot', parameter);
    }
    try {
      const response = await fetch(url, { signal });
      if (!response.ok) {
        throw await problemOf(response, url.href);
      }
      return { url: frameUrl, answer: await response.json() };
    } catch (error) {
      if (!signal.aborted) {
        console.warn(`oer-viewer: hotspots not placed: ${error.message}`);
      }
      return { url: frameUrl, answer: null };
    }
  }

  // Each slotted hotspot at its point of the shown frame (scaled from the frame's pixels to
  // the element's CSS pixels), `data-visible` on those the frame shows; the others hidden.
  #applyPlacements({ url, answer }) {
    if (this.#hotspotWrappers.size === 0) {
      return;
    }
    const rect = this.getBoundingClientRect();
    const placed = new Map((answer?.hotspots ?? []).map((hotspot) => [hotspot.name, hotspot]));
    for (const child of this.children) {
      const name = HOTSPOT_SLOT.exec(child.slot)?.[1];
      const wrapper = name && this.#hotspotWrappers.get(name);
      if (!wrapper) {
        continue;
      }
      const hotspot = placed.get(name);
      const visible = Boolean(hotspot?.visible);
      if (hotspot) {
        const x = (hotspot.x * rect.width) / answer.width;
        const y = (hotspot.y * rect.height) / answer.height;
        wrapper.style.transform = `translate(${x}px, ${y}px) translate(-50%, -50%)`;
      }
      wrapper.hidden = !visible;
      child.toggleAttribute('data-visible', visible);
    }
    this.dispatchEvent(new CustomEvent('hotspots-change', {
      detail: { url, hotspots: answer?.hotspots ?? [] },
    }));
  }

  #weights() {
    const text = this.getAttribute('lights');
    return text ? text.split(',').map(Number) : [];
  }

  async #loadLights() {
    const url = `${this.server}/v1/environments/${encodeURIComponent(this.environment)}`;
    if (url === this.#lightsFor) {
      return;
    }
    this.#lightsFor = url;
    this.#lights = [];  // none of the previous environment's meanwhile
    try {
      const response = await fetch(url);
      if (!response.ok) {
        throw await problemOf(response, url);
      }
      const rig = await response.json();
      if (url !== this.#lightsFor) {
        return;
      }
      this.#lights = rig.lights ?? [];
      this.#dispatchLightsChange();
    } catch (error) {
      this.#lightsFor = null;
      // The frame's own request shows a failure that keeps the view away; the lights' alone
      // (the view is drawn) is only reported.
      this.#report(error, url, { show: false });
    }
  }

  #dispatchLightsChange() {
    const lights = this.lights;
    this.dispatchEvent(new CustomEvent('lights-change', {
      detail: { lights, weights: lights.map((light) => light.weight) },
    }));
  }

  // A failure, as the error event (its `code` and plain-language `message`, with the server's
  // problem verbatim) and, with show, as the message over the view until a frame is shown.
  async #report(error, url, { show = true } = {}) {
    // Only failures that show count: a report that is not shown (the lights' rig failing beside
    // the frame, as under a CORS refusal) must not silence the frame's, whose explanation may
    // take longer (its probes).
    const failure = show ? ++this.#failures : this.#failures;
    const detail = error instanceof ProblemError
      ? { status: error.status, type: error.type, title: error.title, detail: error.message, url }
      : { status: 0, type: null, title: 'Network error', detail: String(error.message ?? error), url };
    const { code, headline, explanation } = await this.#explain(error, detail, url);
    detail.code = code;
    detail.message = `${headline}. ${explanation}`;
    if (show && failure === this.#failures && this.#connected) {
      this.#messageHeadline.textContent = headline;
      this.#messageText.textContent = explanation;
      this.setAttribute('failed', code);
      this.#setWaiting(false);
    }
    this.dispatchEvent(new CustomEvent('error', { detail }));
  }

  // What went wrong, for a shopper: a code to switch on, a headline and one or two sentences.
  // fetch() says nothing of why a request failed; for another origin, two probes tell apart a
  // server that is down (even a no-cors request fails) from one that refuses this page's origin
  // (the no-cors request passes, a CORS one fails).
  async #explain(error, detail, url) {
    const target = new URL(url, location.href);
    const host = target.host;
    if (error instanceof ProblemError) {
      const code = PROBLEM_CODES[error.type] ??
        (error.status === 401 || error.status === 403 ? 'unauthorized'
          : error.status === 404 ? 'not-found'
            : error.status === 429 || error.status === 503 ? 'busy'
              : error.status < 500 ? 'invalid' : 'server');
      return { code, ...PLAIN_WORDS[code](detail) };
    }
    if (!(error instanceof TypeError)) {
      // Not a network failure: an answer the browser could not use (not an image, say).
      return { code: 'server', ...PLAIN_WORDS.server(detail) };
    }
    let code = 'unreachable';
    if (target.origin !== location.origin) {
      const probe = `${this.server}/readyz`;
      const reaches = (mode) => fetch(probe, { mode, cache: 'no-store' }).then(() => true, () => false);
      if (await reaches('no-cors')) {
        code = await reaches('cors') ? 'network' : 'cors';
      }
    }
    return { code, ...PLAIN_WORDS[code]({ ...detail, host }) };
  }

  // The poster: the `poster` attribute's image, else (asked for with the first frame) a small
  // frame of the view from the server.
  #showPoster() {
    const poster = this.getAttribute('poster');
    if (poster) {
      this.#posterController?.abort();
      this.#poster.src = new URL(poster, document.baseURI).href;
    } else if (!this.#posterObjectUrl) {
      this.#poster.removeAttribute('src');
    }
  }

  async #requestPoster() {
    if (this.hasAttribute('poster') || this.hasAttribute('loaded') || this.#posterController ||
        this.#posterObjectUrl) {
      return;
    }
    const controller = new AbortController();
    this.#posterController = controller;
    const url = this.#urlFor('poster');
    try {
      const headers = this.#refinedScenes.has(transferKey(url)) ? {} : { Prefer: 'wait=1' };
      const response = await fetch(url, { signal: controller.signal, headers });
      if (response.ok) {
        const blob = await response.blob();
        if (!controller.signal.aborted && !this.hasAttribute('loaded') && !this.hasAttribute('poster')) {
          this.#posterObjectUrl = URL.createObjectURL(blob);
          this.#poster.src = this.#posterObjectUrl;
        }
      }
    } catch {
      // The frame's own request, asked for at the same time, reports a failure.
    } finally {
      if (this.#posterController === controller) {
        this.#posterController = null;
      }
    }
  }

  // The first frame is shown: the placeholder goes, for good.
  #firstFrameShown() {
    this.setAttribute('loaded', '');
    this.#posterController?.abort();
    this.#posterController = null;
    if (this.#posterObjectUrl) {
      URL.revokeObjectURL(this.#posterObjectUrl);
      this.#posterObjectUrl = null;
      this.#poster.removeAttribute('src');
    }
  }

  // The waiting bar and aria-busy: on while a frame is longer than WAITING_MS in coming, or the
  // one shown is preliminary; aria-busy also until the first frame (unless it failed).
  #setWaiting(on) {
    this.toggleAttribute('waiting', on);
    if (on || (!this.hasAttribute('loaded') && !this.hasAttribute('failed'))) {
      this.setAttribute('aria-busy', 'true');
    } else {
      this.removeAttribute('aria-busy');
    }
  }

  // Asks for a frame at `stage`; a request still in flight is aborted, so only the latest is.
  // A sharp frame shown asks for the full one.
  async #requestFrame(stage) {
    if (!this.#connected || this.getBoundingClientRect().width === 0) {
      return;
    }
    this.#controller?.abort();
    const controller = new AbortController();
    this.#controller = controller;
    const url = this.frameUrl(stage);
    if (!this.hasAttribute('loaded')) {
      this.#requestPoster();
    }
    const started = performance.now();
    const waiting = setTimeout(() => {
      if (this.#controller === controller) {
        this.#setWaiting(true);
      }
    }, WAITING_MS);
    try {
      const scene = transferKey(url);
      const headers = this.#refinedScenes.has(scene) ? {} : { Prefer: 'wait=1' };
      // The hotspots' placement in this frame, asked for beside it.
      this.#placementController?.abort();
      this.#placementController = null;
      const placements = this.#placements(url, controller.signal);
      const response = await fetch(url, { signal: controller.signal, headers });
      if (!response.ok) {
        throw await problemOf(response, url);
      }
      const blob = await response.blob();
      const objectUrl = URL.createObjectURL(blob);
      const next = new Image();
      next.src = objectUrl;
      await next.decode();
      // The frame and its hotspots are shown together (the placement needs no image, and is
      // usually there first).
      const placed = await placements;
      if (controller !== this.#controller) {
        URL.revokeObjectURL(objectUrl);
        return;
      }
      this.#controller = null;
      this.#image.src = objectUrl;
      this.#shownUrl = url;
      this.#applyPlacements(placed);
      this.#failures += 1;  // an explanation still on its way is no longer true
      this.removeAttribute('failed');
      if (!this.hasAttribute('loaded')) {
        this.#firstFrameShown();
      }
      if (this.#objectUrl) {
        URL.revokeObjectURL(this.#objectUrl);
      }
      this.#objectUrl = objectUrl;
      // An asset camera's distance is none of the orbit's, which turning returns to.
      if (!new URL(url, location.href).searchParams.has('camera')) {
        this.#shownDistance = cameraDistance(response.headers.get('X-Oer-Camera')) ?? this.#shownDistance;
      }
      const preliminary = response.headers.get('X-Oer-Preliminary') !== null;
      // A preliminary frame is still a wait: for the frame with its transfer.
      this.#showingPreliminary = preliminary;
      if (!preliminary) {
        this.#refinedScenes.add(scene);
      } else if (stage === 'full') {
        setTimeout(() => {
          if (this.#controller === null && this.frameUrl('full') === url) {
            this.#requestFrame('full');
          }
        }, PRELIMINARY_RETRY_MS);
      }
      this.dispatchEvent(new CustomEvent('load', {
        detail: {
          url,
          stage,
          preview: stage !== 'full',
          preliminary,
          etag: response.headers.get('ETag'),
          serverTiming: response.headers.get('Server-Timing'),
          cache: response.headers.get('X-Oer-Cache'),
          bytes: blob.size,
          width: next.naturalWidth,
          height: next.naturalHeight,
          milliseconds: performance.now() - started,
        },
      }));
      if (stage === 'sharp') {
        this.#requestFrame('full');
      }
    } catch (error) {
      if (controller.signal.aborted) {
        return;
      }
      if (controller === this.#controller) {
        this.#controller = null;
      }
      this.#report(error, url);
    } finally {
      clearTimeout(waiting);
      if (this.#controller === null) {
        this.#setWaiting(this.#showingPreliminary);
      }
      if (this.#pendingPreview && this.#controller === null && this.#previewing) {
        this.#pendingPreview = false;
        this.#requestFrame('preview');
      }
    }
  }

  // A preview now, or as soon as the one in flight is shown (previews go one at a time:
  // aborting each for the next would leave the server rendering frames nobody sees).
  #preview() {
    if (this.#controller && this.#previewing) {
      this.#pendingPreview = true;
    } else {
      this.#previewing = true;
      this.#requestFrame('preview');
    }
    clearTimeout(this.#restTimer);
    this.#restTimer = setTimeout(() => this.#rest(), REST_MILLISECONDS);
  }

  #rest() {
    clearTimeout(this.#restTimer);
    this.#previewing = false;
    this.#pendingPreview = false;
    this.#requestFrame('sharp');
  }

  #setState(set) {
    this.#settingState = true;
    try {
      set();
    } finally {
      this.#settingState = false;
    }
  }

  // Every turn and zoom goes through here: it leaves an asset camera for the orbit.
  #moveCamera(change) {
    const orbit = this.orbit ?? { ...DEFAULT_ORBIT, distance: null };
    this.#setState(() => {
      this.removeAttribute('camera-asset');
      this.orbit = change(orbit);
    });
  }

  // The orbit's distance, or while camera-orbit gives none the server's own (the automatic
  // framing's, named by the shown frame's X-Oer-Camera), so that zooming starts where the view
  // is.
  #distanceOf(orbit) {
    return orbit.distance ?? this.#shownDistance ?? DEFAULT_ORBIT.distance;
  }

  // The span between the two pointers of a pinch.
  #span() {
    const [a, b] = [...this.#pointers.values()];
    return Math.hypot(a.x - b.x, a.y - b.y);
  }

  #startInteraction() {
    this.#dragging = true;
    this.setAttribute('dragging', '');
  }

  #onPointerDown = (event) => {
    if (event.pointerType === 'mouse' && event.button !== 0) {
      return;
    }
    this.setPointerCapture(event.pointerId);
    this.#pointers.set(event.pointerId, { x: event.clientX, y: event.clientY });
    this.#holdTurntable();
    // Without camera-orbit, the distance stays the server's (its framing of the scene).
    const orbit = this.orbit ?? { ...DEFAULT_ORBIT, distance: null };
    if (this.#pointers.size === 2) {
      // A second finger turns the drag into a pinch.
      this.#drag = null;
      this.#pinch = { span: Math.max(1, this.#span()), distance: this.#distanceOf(orbit) };
    } else if (this.#pointers.size === 1) {
      this.#drag = { pointerId: event.pointerId, x: event.clientX, y: event.clientY, orbit };
    }
  };

  #onPointerMove = (event) => {
    if (!this.#pointers.has(event.pointerId)) {
      return;
    }
    this.#pointers.set(event.pointerId, { x: event.clientX, y: event.clientY });
    if (this.#pinch) {
      // Fingers apart bring the eye closer: the distance scales as the span's inverse.
      const pinch = this.#pinch;
      this.#startInteraction();
      this.#moveCamera((orbit) => ({
        ...orbit, distance: pinch.distance * pinch.span / Math.max(1, this.#span()),
      }));
      this.#preview();
      return;
    }
    const drag = this.#drag;
    if (!drag || drag.pointerId !== event.pointerId) {
      return;
    }
    const dx = event.clientX - drag.x;
    const dy = event.clientY - drag.y;
    if (!this.#dragging && Math.hypot(dx, dy) < 2) {
      return;
    }
    this.#startInteraction();
    // Dragging right turns the product right (the eye goes left); dragging down raises the eye.
    this.#moveCamera(() => ({
      yaw: drag.orbit.yaw - dx * DEGREES_PER_PIXEL,
      pitch: drag.orbit.pitch + dy * DEGREES_PER_PIXEL,
      distance: drag.orbit.distance,
    }));
    this.#preview();
  };

  #onPointerUp = (event) => {
    if (!this.#pointers.delete(event.pointerId)) {
      return;
    }
    this.#holdTurntable();
    // The finger left after a pinch does not start a drag: the view would jump to it.
    if (this.#pinch || event.pointerId === this.#drag?.pointerId) {
      this.#pinch = null;
      this.#drag = null;
    }
    if (this.#pointers.size === 0 && this.#dragging) {
      this.#dragging = false;
      this.removeAttribute('dragging');
      this.#rest();
    }
  };

  // The turntable turns the orbit's yaw on every animation frame while auto-rotate is set,
  // through previews (one in flight at a time, as a drag's); pointers, the wheel and keys hold
  // it for TURNTABLE_DELAY_MILLISECONDS, and switching it off rests on the full frame.
  #updateTurntable() {
    const table = this.#turntable;
    const turning = table.frame !== 0;
    cancelAnimationFrame(table.frame);
    table.frame = 0;
    if (this.#connected && this.hasAttribute('auto-rotate')) {
      // Set by the first animation frame: its timestamp (the frame's start) may precede
      // performance.now() here, which would make the first turn no turn at all.
      table.last = null;
      table.frame = requestAnimationFrame(this.#turn);
    } else if (turning && this.#connected) {
      this.#rest();
    }
  }

  #holdTurntable() {
    this.#turntable.heldUntil = performance.now() + TURNTABLE_DELAY_MILLISECONDS;
  }

  #turn = (now) => {
    const table = this.#turntable;
    table.frame = requestAnimationFrame(this.#turn);
    const seconds = table.last === null ? 0 : Math.max(0, now - table.last) / 1000;
    table.last = now;
    if (seconds === 0) {
      return;
    }
    if (this.#pointers.size > 0 || now < table.heldUntil) {
      return;
    }
    this.#moveCamera((orbit) => ({ ...orbit, yaw: orbit.yaw + TURNTABLE_DEGREES_PER_SECOND * seconds }));
    this.#preview();
  };

  #onWheel = (event) => {
    event.preventDefault();
    this.#holdTurntable();
    const pixels = event.deltaMode === WheelEvent.DOM_DELTA_LINE ? event.deltaY * 16 : event.deltaY;
    this.#moveCamera((orbit) => ({
      ...orbit,
      distance: this.#distanceOf(orbit) * Math.exp(pixels * WHEEL_ZOOM_PER_PIXEL),
    }));
    this.#preview();
  };

  #onKeyDown = (event) => {
    const turns = {
      ArrowLeft: [KEY_STEP_DEGREES, 0, 1], ArrowRight: [-KEY_STEP_DEGREES, 0, 1],
      ArrowUp: [0, -KEY_STEP_DEGREES, 1], ArrowDown: [0, KEY_STEP_DEGREES, 1],
      '+': [0, 0, 0.9], '=': [0, 0, 0.9], '-': [0, 0, 1 / 0.9],
    };
    const turn = turns[event.key];
    if (!turn) {
      return;
    }
    event.preventDefault();
    this.#holdTurntable();
    const [yaw, pitch, zoom] = turn;
    this.#moveCamera((orbit) => ({
      yaw: orbit.yaw + yaw,
      pitch: orbit.pitch + pitch,
      distance: zoom === 1 ? orbit.distance : this.#distanceOf(orbit) * zoom,
    }));
    this.#requestFrame('sharp');
  };
}

// |eye - target| of an X-Oer-Camera header (`eye=x,y,z; target=x,y,z; ...`); null without one.
function cameraDistance(header) {
  const vector = (name) => new RegExp(`${name}=([^;]+)`).exec(header ?? '')?.[1].split(',').map(Number);
  const [eye, target] = [vector('eye'), vector('target')];
  if (!eye || !target) {
    return null;
  }
  const distance = Math.hypot(...eye.map((value, axis) => value - target[axis]));
  return Number.isFinite(distance) ? distance : null;
}

// The error event's `code` for the server's problem types (api/openapi.yaml); other answers go by
// their status.
const PROBLEM_CODES = {
  '/v1/problems/unknown-id': 'not-found',
  '/v1/problems/not-found': 'not-found',
  '/v1/problems/map-not-stored': 'not-found',
  '/v1/problems/invalid-parameter': 'invalid',
  '/v1/problems/malformed-request': 'invalid',
  '/v1/problems/limit-exceeded': 'invalid',
  '/v1/problems/uri-too-long': 'invalid',
  '/v1/problems/unauthorized': 'unauthorized',
  '/v1/problems/too-many-renders': 'busy',
  '/v1/problems/too-many-connections': 'busy',
  '/v1/problems/unavailable': 'busy',
};

// Per code, the words a shopper reads over the view (and the error event's `message`); the
// server's own `detail` stays verbatim where it says what a person can act on.
const PLAIN_WORDS = {
  unreachable: ({ host }) => ({
    headline: 'The 3D view cannot load',
    explanation: `Its server (${host}) does not answer. Check the connection, then reload the page.`,
  }),
  cors: ({ host }) => ({
    headline: 'The 3D view cannot load on this site',
    explanation: `Its server (${host}) does not allow pages of ${location.origin}. The site's ` +
      `owner can allow them: oer-server --cors-origins ${location.origin}.`,
  }),
  network: () => ({
    headline: 'The 3D view stopped loading',
    explanation: 'The connection to its server broke off. Reload the page to try again.',
  }),
  'not-found': ({ detail }) => ({
    headline: 'This product or environment is not available',
    explanation: `It may have been removed, or the link is old or mistyped (${detail}).`,
  }),
  invalid: ({ detail }) => ({
    headline: 'This view cannot be shown',
    explanation: `The link or a setting asks for something the server refuses: ${detail}`,
  }),
  unauthorized: () => ({
    headline: 'The 3D view\'s server refused this page',
    explanation: 'It asks for a key that this page does not have.',
  }),
  busy: () => ({
    headline: 'The 3D view\'s server is busy',
    explanation: 'Try again in a moment.',
  }),
  server: ({ status, detail }) => ({
    headline: 'The 3D view could not be drawn',
    explanation: `${status ? `The server failed (${status}): ` : ''}${detail}`,
  }),
};

// A GET /v1/render query as the RenderRequest it names: the query's members have the body's
// names and values (api/openapi.yaml), but for the body's nesting (objects, camera, shadows) and
// its types (numbers, booleans, arrays). A value that is not a number stays text, so that the
// server refuses it naming its member, as it refuses the query's.
function renderRequestOf(query) {
  const number = (text) => (text.trim() !== '' && Number.isFinite(Number(text)) ? Number(text) : text);
  const numbers = (text) => text.split(',').map(number);
  const onOff = (text) => (text === 'on' ? true : text === 'off' ? false : text);
  const request = { environment: query.get('environment') };
  // base_color, base_color_material and variant are every mesh's in the query.
  const everyObject = {};
  if (query.has('base_color')) {
    everyObject.base_color = numbers(query.get('base_color'));
  }
  for (const name of ['base_color_material', 'variant']) {
    if (query.has(name)) {
      everyObject[name] = query.get(name);
    }
  }
  request.objects = query.getAll('mesh').map((mesh) => ({ mesh, ...everyObject }));
  for (const name of ['width', 'height', 'samples', 'quality', 'exposure', 'environment_yaw']) {
    if (query.has(name)) {
      request[name] = number(query.get(name));
    }
  }
  for (const name of ['format', 'background']) {
    if (query.has(name)) {
      request[name] = query.get(name);
    }
  }
  if (query.has('lights')) {
    request.lights = numbers(query.get('lights'));
  }
  if (query.has('ground')) {
    request.ground = query.get('ground') === 'shadow' ? 'shadow' : onOff(query.get('ground'));
  }
  const shadows = {};
  for (const [parameter, member, read] of [['shadows', 'enabled', onOff],
                                           ['shadow_resolution', 'resolution', number],
                                           ['shadow_filter', 'filter', String],
                                           ['shadow_softness', 'softness', number],
                                           ['shadow_intensity', 'intensity', number]]) {
    if (query.has(parameter)) {
      shadows[member] = read(query.get(parameter));
    }
  }
  if (Object.keys(shadows).length > 0) {
    request.shadows = shadows;
  }
  const target = query.has('target') ? numbers(query.get('target')) : undefined;
  if (query.has('camera')) {
    // camera=asset:N (an index) or asset:NAME, as the server reads it.
    const which = query.get('camera').replace(/^asset:/, '');
    request.camera = { asset: /^\d+$/.test(which) ? Number(which) : which };
  } else if (['yaw', 'pitch', 'distance'].some((name) => query.has(name))) {
    const orbit = {};
    for (const name of ['yaw', 'pitch', 'distance']) {
      if (query.has(name)) {
        orbit[name] = number(query.get(name));
      }
    }
    request.camera = { orbit: target ? { ...orbit, target } : orbit };
  } else if (target) {
    request.camera = { target };
  }
  return request;
}

// An answer that is not 2xx, with the problem+json `detail` verbatim when there is one, and its
// `type` (what a page switches on; RFC 9457: absent means about:blank).
class ProblemError extends Error {
  constructor(status, type, title, detail) {
    super(detail);
    this.status = status;
    this.type = type;
    this.title = title;
  }
}

export async function problemOf(response, url) {
  let body = {};
  try {
    body = await response.json();
  } catch {
    // Not problem+json (a proxy's page, say): the status line is all there is.
  }
  return new ProblemError(response.status, body.type ?? 'about:blank',
                          body.title ?? response.statusText,
                          body.detail ?? `${response.status} ${response.statusText} from ${url}`);
}

if (!customElements.get('oer-viewer')) {
  customElements.define('oer-viewer', OerViewer);
}
