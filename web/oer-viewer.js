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

const STYLE = `
  :host { display: block; position: relative; overflow: hidden; touch-action: none;
          min-width: 1px; min-height: 1px; cursor: grab; outline: none; }
  :host(:focus-visible) { box-shadow: inset 0 0 0 3px #4d90fe; }
  :host([dragging]) { cursor: grabbing; }
  img { display: block; width: 100%; height: 100%; user-select: none;
        -webkit-user-drag: none; pointer-events: none; }
  .waiting { display: none; position: absolute; left: 0; top: 0; height: 4px; width: 30%;
             background: #4d90fe; animation: waiting 1.2s ease-in-out infinite; }
  :host([waiting]) .waiting { display: block; }
  @keyframes waiting { from { left: -30%; } to { left: 100%; } }
  @media (prefers-reduced-motion: reduce) {
    .waiting { width: 100%; animation: none; opacity: 0.6; }
  }
`;

export class OerViewer extends HTMLElement {
  static observedAttributes = [
    'server', 'mesh', 'environment', 'lights', 'camera-orbit', 'camera-target', 'camera-asset',
    'exposure', 'background', 'ground', 'shadows', 'shadow-intensity', 'shadow-softness',
    'environment-yaw', 'base-color', 'base-color-material', 'variant', 'auto-rotate',
  ];

  #image;
  #waitingBar;
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

  constructor() {
    super();
    const root = this.attachShadow({ mode: 'open' });
    const style = document.createElement('style');
    style.textContent = STYLE;
    this.#image = document.createElement('img');
    this.#image.alt = '';
    this.#image.part = 'frame';
    this.#waitingBar = document.createElement('div');
    this.#waitingBar.className = 'waiting';
    this.#waitingBar.part = 'waiting';
    root.append(style, this.#image, this.#waitingBar);
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
    this.#resizeObserver.observe(this);
    this.#loadLights();
    this.#updateTurntable();
  }

  disconnectedCallback() {
    this.#connected = false;
    this.#resizeObserver.disconnect();
    this.#controller?.abort();
    this.#controller = null;
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
    const preview = stage === 'preview';
    const rect = this.getBoundingClientRect();
    const ratio = window.devicePixelRatio || 1;
    const scale = preview ? PREVIEW.scale : 1;
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
    const asset = this.getAttribute('camera-asset');
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
      this.#dispatchError(error, url);
    }
  }

  #dispatchLightsChange() {
    const lights = this.lights;
    this.dispatchEvent(new CustomEvent('lights-change', {
      detail: { lights, weights: lights.map((light) => light.weight) },
    }));
  }

  #dispatchError(error, url) {
    const detail = error instanceof ProblemError
      ? { status: error.status, type: error.type, title: error.title, detail: error.message, url }
      : { status: 0, type: null, title: 'Network error', detail: String(error.message ?? error), url };
    this.dispatchEvent(new CustomEvent('error', { detail }));
  }

  // The waiting bar and aria-busy: on while a frame is longer than WAITING_MS in coming, or the
  // one shown is preliminary.
  #setWaiting(on) {
    this.toggleAttribute('waiting', on);
    if (on) {
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
    const started = performance.now();
    const waiting = setTimeout(() => {
      if (this.#controller === controller) {
        this.#setWaiting(true);
      }
    }, WAITING_MS);
    try {
      const scene = transferKey(url);
      const headers = this.#refinedScenes.has(scene) ? {} : { Prefer: 'wait=1' };
      const response = await fetch(url, { signal: controller.signal, headers });
      if (!response.ok) {
        throw await problemOf(response, url);
      }
      const blob = await response.blob();
      const objectUrl = URL.createObjectURL(blob);
      const next = new Image();
      next.src = objectUrl;
      await next.decode();
      if (controller !== this.#controller) {
        URL.revokeObjectURL(objectUrl);
        return;
      }
      this.#controller = null;
      this.#image.src = objectUrl;
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
      this.#dispatchError(error, url);
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
      table.last = performance.now();
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
    const seconds = Math.max(0, now - table.last) / 1000;
    table.last = now;
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
