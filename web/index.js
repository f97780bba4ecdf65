// The page at /: the controls of the view around one <oer-viewer> (index.html).
import { equirectangularUv, problemOf } from '/web/oer-viewer.js';

// The page's view state lives in the element's attributes and, mirrored, in the URL's
// query, so that a shared link reproduces the same frame (the same ETag).

const viewer = document.getElementById('viewer');
// stateAttributes: declared by index.html's inline script, which applies the URL's query.

const exposure = document.getElementById('exposure');
const exposureValue = document.getElementById('exposure-value');
const background = document.getElementById('background');
const backgroundColor = document.getElementById('background-color');
const ground = document.getElementById('ground');
const shadows = document.getElementById('shadows');
const shadowIntensity = document.getElementById('shadow-intensity');
const shadowIntensityValue = document.getElementById('shadow-intensity-value');
const shadowSoftness = document.getElementById('shadow-softness');
const shadowSoftnessValue = document.getElementById('shadow-softness-value');
const environmentYaw = document.getElementById('environment-yaw');
const environmentYawValue = document.getElementById('environment-yaw-value');
const showState = () => {
  exposure.value = viewer.getAttribute('exposure') ?? '0';
  exposureValue.value = exposure.value;
  const backgroundValue = viewer.getAttribute('background') || 'env';
  background.value = backgroundValue.startsWith('#') ? 'color' : backgroundValue;
  backgroundColor.hidden = background.value !== 'color';
  if (backgroundValue.startsWith('#')) {
    backgroundColor.value = backgroundValue.toLowerCase();
  }
  ground.value = viewer.getAttribute('ground') || 'on';
  shadows.checked = viewer.getAttribute('shadows') !== 'off';
  shadowIntensity.value = viewer.getAttribute('shadow-intensity') ?? '1';
  shadowIntensityValue.value = shadowIntensity.value;
  shadowSoftness.value = viewer.getAttribute('shadow-softness') ?? '1';
  shadowSoftnessValue.value = shadowSoftness.value;
  environmentYaw.value = viewer.getAttribute('environment-yaw') ?? '0';
  environmentYawValue.value = environmentYaw.value;
};
showState();

// The link also names the uploads it shows (`mesh-name`, `environment-name`: the user's file
// names, which the server does not keep), so that whoever opens it sees them in the pickers.
// uploadNames is filled below, from the link and from this page's uploads. It carries the
// hotspots placed in the page too (`hotspot`, below).
const uploadNames = { mesh: new Map(), environment: new Map() };
const writeLink = () => {
  const next = new URLSearchParams();
  for (const name of stateAttributes) {
    const value = viewer.getAttribute(name);
    if (value !== null && value !== '') {
      next.set(name, value);
    }
  }
  for (const attribute of ['mesh', 'environment']) {
    const name = uploadNames[attribute].get(viewer.getAttribute(attribute));
    if (name) {
      next.set(`${attribute}-name`, name);
    }
  }
  for (const hotspot of viewer.querySelectorAll(':scope > .hotspot')) {
    next.append('hotspot', hotspotLinkText(hotspot));
  }
  const text = next.toString();
  history.replaceState(null, '', text ? `?${text}` : location.pathname);
};
new MutationObserver(() => {
  writeLink();
  showState();
}).observe(viewer, { attributes: true, attributeFilter: stateAttributes });

document.getElementById('reset').addEventListener('click', () => viewer.resetView());
// Sliders adjust(): previews while they move, the full frame when they rest.
exposure.addEventListener('input', () => {
  exposureValue.value = exposure.value;
  viewer.adjust('exposure', Number(exposure.value) === 0 ? null : exposure.value);
});
// The attributes hold only what differs from GET /v1/render's defaults (environment
// background, ground on, no rotation), so the default view's link stays short.
const applyBackground = () => {
  if (background.value === 'env') {
    viewer.removeAttribute('background');
  } else {
    viewer.setAttribute('background',
                        background.value === 'color' ? backgroundColor.value : background.value);
  }
};
background.addEventListener('change', applyBackground);
backgroundColor.addEventListener('input', applyBackground);
// The ground: an opaque floor (GET /v1/render's default, no attribute), a shadow catcher or none.
ground.addEventListener('change', () => {
  if (ground.value === 'on') {
    viewer.removeAttribute('ground');
  } else {
    viewer.setAttribute('ground', ground.value);
  }
});
// Shadows: absent when on (the default) and 'off' when off.
shadows.addEventListener('change', () => {
  if (shadows.checked) {
    viewer.removeAttribute('shadows');
  } else {
    viewer.setAttribute('shadows', 'off');
  }
});
// Shadow strength (the shadow-only floor's) and softness: absent at 1, the defaults.
for (const [slider, output, attribute] of [[shadowIntensity, shadowIntensityValue, 'shadow-intensity'],
                                           [shadowSoftness, shadowSoftnessValue, 'shadow-softness']]) {
  slider.addEventListener('input', () => {
    output.value = slider.value;
    viewer.adjust(attribute, Number(slider.value) === 1 ? null : slider.value);
  });
}
environmentYaw.addEventListener('input', () => {
  environmentYawValue.value = environmentYaw.value;
  viewer.adjust('environment-yaw', Number(environmentYaw.value) === 0 ? null : environmentYaw.value);
});

// The turntable is behaviour, not view state: not in the URL.
const turntable = document.getElementById('turntable');
turntable.addEventListener('change', () => viewer.toggleAttribute('auto-rotate', turntable.checked));

// Colors: base-color as #rrggbb (sRGB), absent for the product's own materials; on one part
// (base-color-material, a material's name) or on the whole product.
const colors = [...document.querySelectorAll('input[name=color]')];
const colorPart = document.getElementById('color-part');
const colorPartGroup = document.getElementById('color-part-group');
const showColor = () => {
  const value = (viewer.getAttribute('base-color') ?? '').toLowerCase();
  for (const color of colors) {
    color.checked = color.value === value;
  }
  colorPart.value = viewer.getAttribute('base-color-material') ?? '';
};
for (const color of colors) {
  color.addEventListener('change', () => {
    if (color.value) {
      if (colorPart.value) {
        viewer.setAttribute('base-color-material', colorPart.value);
      }
      viewer.setAttribute('base-color', color.value);
    } else {
      viewer.removeAttribute('base-color-material');
      viewer.removeAttribute('base-color');
    }
  });
}
colorPart.addEventListener('change', () => {
  if (!viewer.hasAttribute('base-color')) {
    return;  // the part waits for a color
  }
  if (colorPart.value) {
    viewer.setAttribute('base-color-material', colorPart.value);
  } else {
    viewer.removeAttribute('base-color-material');
  }
});
showColor();
new MutationObserver(showColor)
  .observe(viewer, { attributeFilter: ['base-color', 'base-color-material'] });

// The parts a color can go to: the product's materials, by name, each once; hidden for a
// product of one material.
const showParts = (materials) => {
  const names = [...new Set(materials.map((material) => material.name).filter(Boolean))];
  colorPart.replaceChildren(new Option('the whole product', ''),
                            ...names.map((name) => new Option(name, name)));
  colorPartGroup.hidden = names.length < 2;
  showColor();
};

// The product's own variants (KHR_materials_variants) as swatches, each colored from its
// swatch material's base color; hidden for a product without variants.
const productVariants = document.getElementById('product-variants');
const productVariantChoices = document.getElementById('product-variant-choices');
// The product's variants' names, for "All variants" (below), enabled only when there are some.
const allVariantsButton = document.getElementById('all-variants');
let productVariantNames = [];
const srgbHex = (linear) => `#${linear.slice(0, 3).map((value) => {
  const v = Math.min(1, Math.max(0, value));
  const encoded = v <= 0.0031308 ? 12.92 * v : 1.055 * v ** (1 / 2.4) - 0.055;
  return Math.round(255 * encoded).toString(16).padStart(2, '0');
}).join('')}`;
const showProductVariant = () => {
  const value = viewer.getAttribute('variant') ?? '';
  for (const input of productVariantChoices.querySelectorAll('input')) {
    input.checked = input.value === value;
  }
};
const showProductVariants = (variants) => {
  const choice = (name, label, swatch) => {
    const input = document.createElement('input');
    input.type = 'radio';
    input.name = 'product-variant';
    input.value = name;
    input.addEventListener('change', () => {
      if (name) {
        viewer.setAttribute('variant', name);
      } else {
        viewer.removeAttribute('variant');
      }
    });
    const element = document.createElement('label');
    element.append(input);
    if (swatch) {
      const span = document.createElement('span');
      span.className = 'swatch';
      span.style.background = srgbHex(swatch.base_color);
      element.append(span);
    }
    element.append(` ${label}`);
    return element;
  };
  productVariantChoices.replaceChildren(
    choice('', 'As shipped', null),
    ...variants.map((variant) => choice(variant.name, variant.name, variant.swatch)));
  productVariants.hidden = variants.length === 0;
  productVariantNames = variants.map((variant) => variant.name);
  allVariantsButton.disabled = variants.length === 0;
  showProductVariant();
};
new MutationObserver(showProductVariant).observe(viewer, { attributeFilter: ['variant'] });

// The environment's preview with each light's position marked by its number, in its color;
// a light switched off is marked hollow.
const lightMapImage = document.getElementById('light-map-image');
const lightMap = document.getElementById('light-map');
const showLightMap = (lights) => {
  if (lightMapImage.getAttribute('src') !== viewer.environmentPreviewUrl) {
    lightMapImage.src = viewer.environmentPreviewUrl;
  }
  lightMap.querySelectorAll('.marker').forEach((marker) => marker.remove());
  for (const light of lights) {
    const { u, v } = equirectangularUv(light.direction);
    const marker = document.createElement('span');
    marker.className = light.weight > 0 ? 'marker' : 'marker off';
    marker.textContent = String(light.index + 1);
    marker.style.left = `${(100 * u).toFixed(2)}%`;
    marker.style.top = `${(100 * v).toFixed(2)}%`;
    marker.style.setProperty('--light-color', lightColor(light));
    marker.setAttribute('aria-hidden', 'true');
    lightMap.append(marker);
  }
};

// A light's color at full brightness (its intensity over its largest channel), for its swatch
// and its marker.
function lightColor(light) {
  const peak = Math.max(...light.intensity, 1e-9);
  const [r, g, b] = light.intensity.map((value) => Math.round(255 * value / peak));
  return `rgb(${r} ${g} ${b})`;
}

// A switch and a dimmer per light of the environment, labelled with its color and share of
// the energy. The switch toggles between 0 and the light's last weight above 0, so switching
// a dimmed light back on restores its level.
const lightsPanel = document.getElementById('lights');
const switches = document.getElementById('light-switches');
const lastWeights = [];
const showLights = ({ detail: { lights, weights } }) => {
  lightsPanel.hidden = lights.length === 0;
  showLightMap(lights);
  if (switches.children.length !== lights.length) {
    lastWeights.length = 0;  // another environment's lights
    switches.replaceChildren(...lights.map((light) => {
      const name = `Light ${light.index + 1}`;
      const row = document.createElement('span');
      row.className = 'light';
      const label = document.createElement('label');
      const box = document.createElement('input');
      box.type = 'checkbox';
      box.addEventListener('change', () =>
        viewer.setLight(light.index, box.checked ? (lastWeights[light.index] ?? 1) : 0));
      const swatch = document.createElement('span');
      swatch.className = 'swatch';
      const peak = Math.max(...light.intensity, 1e-9);
      const [r, g, b] = light.intensity.map((value) => Math.round(255 * value / peak));
      swatch.style.background = `rgb(${r} ${g} ${b})`;
      label.append(box, swatch, `${name} (${Math.round(100 * light.luminance_share)} %)`);
      // GET /v1/render takes each weight in [0, 4].
      const dimmer = document.createElement('input');
      dimmer.type = 'range';
      dimmer.className = 'dimmer';
      dimmer.min = '0';
      dimmer.max = '4';
      dimmer.step = '0.05';
      dimmer.setAttribute('aria-label', `${name} weight`);
      const level = document.createElement('output');
      level.setAttribute('aria-hidden', 'true');
      dimmer.addEventListener('input', () =>
        viewer.setLight(light.index, Number(dimmer.value), { adjusting: true }));
      row.append(label, dimmer, level);
      return row;
    }));
  }
  weights.forEach((weight, index) => {
    const row = switches.children[index];
    row.querySelector('input[type=checkbox]').checked = weight > 0;
    row.querySelector('input[type=range]').value = String(weight);
    row.querySelector('output').value = weight.toFixed(2);
    if (weight > 0) {
      lastWeights[index] = weight;
    }
  });
};
viewer.addEventListener('lights-change', showLights);
// The element is defined before this module runs, and may have loaded the lights already (its
// answer can come before this file does): show those.
const loadedLights = viewer.lights;
showLights({ detail: { lights: loadedLights, weights: loadedLights.map((light) => light.weight) } });
document.getElementById('all-on').addEventListener('click', () => viewer.removeAttribute('lights'));
document.getElementById('all-off').addEventListener('click', () =>
  viewer.setAttribute('lights', viewer.lights.map(() => 0).join(',')));

// The status line: size, bytes, time in the browser and on the server (or that the server's
// cache answered), and while dragging the previews shown per second since the press.
// The status is a live region: it changes only on settled states (a full frame, an error), so
// that a screen reader is not flooded with every preview; the previews' rate while dragging goes
// beside it, shown but not announced.
const status = document.getElementById('status');
const previewRate = document.getElementById('preview-rate');
const setStatus = (text, { error = false } = {}) => {
  if (status.textContent !== text) {
    status.textContent = text;
  }
  status.classList.toggle('error', error);
};
let drag = { started: 0, previews: 0 };
viewer.addEventListener('pointerdown', () => { drag = { started: performance.now(), previews: 0 }; });
viewer.addEventListener('pointerup', () => { previewRate.textContent = ''; });
viewer.addEventListener('load', ({ detail }) => {
  if (detail.stage === 'preview' && viewer.hasAttribute('dragging')) {
    drag.previews += 1;
    const seconds = (performance.now() - drag.started) / 1000;
    previewRate.textContent = `${(drag.previews / seconds).toFixed(1)} fps`;
  }
  if (detail.stage !== 'full' || detail.preliminary) {
    return;  // not settled yet
  }
  // Server-Timing lists the passes, their `total`, then `encode` (server/README.md); a frame
  // from the server's cache has none.
  const timing = Object.fromEntries((detail.serverTiming ?? '').split(',').map((entry) => {
    const [name, ...fields] = entry.trim().split(';');
    const duration = fields.find((field) => field.startsWith('dur='));
    return [name, Number(duration?.slice(4) ?? 0)];
  }));
  const server = (timing.total ?? 0) + (timing.encode ?? 0);
  setStatus([
    `${detail.width}×${detail.height}`,
    `${(detail.bytes / 1024).toFixed(0)} KiB`,
    `${detail.milliseconds.toFixed(0)} ms`,
    detail.cache === 'hit' ? 'cached' : `server ${server.toFixed(0)} ms`,
  ].join(', '));
});
// The frame in view at full quality (PNG, 4 samples), saved through a temporary link.
const download = document.getElementById('download');
download.addEventListener('click', async () => {
  download.disabled = true;
  try {
    const blob = await viewer.snapshot();
    const link = document.createElement('a');
    link.href = URL.createObjectURL(blob);
    link.download = 'oer-frame.png';
    link.click();
    // The download has taken the Blob by then; a minute is ample.
    setTimeout(() => URL.revokeObjectURL(link.href), 60000);
  } catch (error) {
    setStatus(`The PNG could not be made: ${error.message}`, { error: true });
  } finally {
    download.disabled = false;
  }
});

// Hotspots. In the place mode a click on the product (a press released where it began, not a
// drag) asks the server which point of its surface the pixel shows (viewer.pick) and adds a
// numbered hotspot there: a point of a triangle, which stays on that point of the surface
// through every orbit and hides whenever the product is in front of it.
const placeHotspot = document.getElementById('place-hotspot');
const clearHotspots = document.getElementById('clear-hotspots');
const CLICK_SLOP_PX = 4;
let placing = false;
let pressedAt = null;
let hotspotsPlaced = 0;
// The page's hotspots are a slotted button each, named by its slot (`hotspot-NAME`), its point
// in data-surface: "OBJECT PRIMITIVE TRIANGLE A B C" (web/README.md).
function addHotspot(name, surface) {
  const hotspot = document.createElement('button');
  hotspot.type = 'button';
  hotspot.className = 'hotspot';
  hotspot.slot = `hotspot-${name}`;
  hotspot.dataset.surface = surface;
  hotspot.textContent = name;
  hotspot.setAttribute('aria-label', `Hotspot ${name}`);
  viewer.append(hotspot);
  clearHotspots.hidden = false;
}
// In the link each is `hotspot=NAME OBJECT PRIMITIVE TRIANGLE A B C`: its name, then its
// data-surface; the weights rounded to 4 decimals when placed keep it short (a ten-thousandth
// of a triangle is far below a pixel, and the server takes weights summing to 1 within 1e-3).
const BARYCENTRIC_DECIMALS = 4;
function hotspotLinkText(hotspot) {
  return `${hotspot.slot.replace(/^hotspot-/, '')} ${hotspot.dataset.surface}`;
}
// A link's hotspot entry as { name, surface }, or an Error saying in plain words why it cannot
// be one: the link may be mangled, or made to harm (its name becomes a slot and a button's
// text, its numbers a request), so each part is checked against what the server takes
// (api/openapi.yaml, HotspotName and SurfaceHotspot).
const HOTSPOT_NAME = /^[A-Za-z0-9_-]{1,64}$/;
const SURFACE_INDEX = /^\d{1,9}$/;  // an object's, a primitive's or a triangle's
function hotspotFromLink(text, takenNames) {
  const [name, ...fields] = text.trim().split(/\s+/);
  const shown = name.length > 24 ? `${name.slice(0, 24)}…` : name;
  if (!HOTSPOT_NAME.test(name)) {
    return new Error(`"${shown}" is not a hotspot name (1 to 64 letters, digits, - or _)`);
  }
  if (takenNames.has(name)) {
    return new Error(`hotspot ${name} is named twice`);
  }
  const indices = fields.slice(0, 3);
  const weights = fields.slice(3).map(Number);
  const weightSum = weights.reduce((sum, weight) => sum + weight, 0);
  if (fields.length !== 6 || !indices.every((index) => SURFACE_INDEX.test(index)) ||
      !weights.every((weight) => weight >= 0 && weight <= 1) || Math.abs(weightSum - 1) > 1e-3) {
    return new Error(`hotspot ${name} does not name a point of the product's surface`);
  }
  return { name, surface: [...indices.map(Number), ...weights].join(' ') };
}
// GET /v1/hotspots takes at most this many; a link with more is not the page's own.
const MAX_LINK_HOTSPOTS = 256;
function restoreLinkHotspots() {
  const entries = initialQuery.getAll('hotspot');
  const taken = new Set();
  const refused = [];
  for (const [index, text] of entries.entries()) {
    const hotspot = index < MAX_LINK_HOTSPOTS ? hotspotFromLink(text, taken)
      : new Error(`more than ${MAX_LINK_HOTSPOTS} hotspots`);
    if (hotspot instanceof Error) {
      refused.push(hotspot.message);
      continue;
    }
    taken.add(hotspot.name);
    addHotspot(hotspot.name, hotspot.surface);
    // A hotspot placed next gets the next number after the link's.
    if (/^\d+$/.test(hotspot.name)) {
      hotspotsPlaced = Math.max(hotspotsPlaced, Number(hotspot.name));
    }
  }
  if (refused.length > 0) {
    say(`This link's hotspots are not all shown: ${refused.length} of ${entries.length} left ` +
        `out (${refused[0]}).`, { error: true });
    writeLink();  // the link shows what the page shows
  }
}
placeHotspot.addEventListener('click', () => {
  placing = !placing;
  placeHotspot.setAttribute('aria-pressed', String(placing));
  viewer.toggleAttribute('placing', placing);
  if (placing) {
    setStatus('Click the product where a hotspot goes.');
  }
});
clearHotspots.addEventListener('click', () => {
  viewer.querySelectorAll('.hotspot').forEach((hotspot) => hotspot.remove());
  clearHotspots.hidden = true;
  writeLink();
});
viewer.addEventListener('pointerdown', (event) => { pressedAt = { x: event.clientX, y: event.clientY }; });
viewer.addEventListener('click', async (event) => {
  const still = pressedAt &&
    Math.hypot(event.clientX - pressedAt.x, event.clientY - pressedAt.y) <= CLICK_SLOP_PX;
  if (!placing || !still || event.target !== viewer) {
    return;  // a drag, or a click on a hotspot itself
  }
  try {
    const surface = await viewer.pick(event.clientX, event.clientY);
    if (!surface) {
      setStatus('No product there: click the product itself to place a hotspot.');
      return;
    }
    hotspotsPlaced += 1;
    const point = [surface.object, surface.primitive, surface.triangle,
                   ...surface.barycentric.map((weight) => Number(weight.toFixed(BARYCENTRIC_DECIMALS)))]
      .join(' ');
    addHotspot(String(hotspotsPlaced), point);
    writeLink();
    setStatus(`Hotspot ${hotspotsPlaced} placed: data-surface="${point}"`);
  } catch (error) {
    setStatus(`The hotspot could not be placed: ${error.message}`, { error: true });
  }
});

// The element shows the failure over the view; the status repeats its plain words, announced.
viewer.addEventListener('error', ({ detail }) => setStatus(detail.message, { error: true }));

// Presets and uploads. The Product and Environment pickers list the server's presets
// (GET /v1/presets), what was uploaded in this page, and the element's id when it is neither
// (a shared link's upload, named by its short id), so that they always show the view's state.
// A file (the Upload… button, or dropped anywhere on the page) goes to POST /v1/meshes or
// POST /v1/environments by its extension, through XMLHttpRequest, whose upload.onprogress
// reports the bytes sent (fetch reports none).
const meshPicker = document.getElementById('mesh-picker');
const environmentPicker = document.getElementById('environment-picker');
const uploadGroup = document.getElementById('upload-group');
const uploadButton = document.getElementById('upload');
const uploadFile = document.getElementById('upload-file');
const uploadProgress = document.getElementById('upload-progress');
const uploadStatus = document.getElementById('upload-status');
const dropHint = document.getElementById('drop-hint');

// Per extension: the attribute the upload's id goes to, the route, and the Content-Type the
// route reads the file's format from (api/openapi.yaml).
const UPLOAD_KINDS = {
  glb: { attribute: 'mesh', route: '/v1/meshes', type: 'model/gltf-binary' },
  gltf: { attribute: 'mesh', route: '/v1/meshes', type: 'model/gltf+json' },
  obj: { attribute: 'mesh', route: '/v1/meshes', type: 'model/obj' },
  hdr: { attribute: 'environment', route: '/v1/environments', type: 'image/vnd.radiance' },
  exr: { attribute: 'environment', route: '/v1/environments', type: 'image/x-exr' },
  // A phone's panorama: low dynamic range, decoded from sRGB by the server.
  jpg: { attribute: 'environment', route: '/v1/environments', type: 'image/jpeg' },
  jpeg: { attribute: 'environment', route: '/v1/environments', type: 'image/jpeg' },
  png: { attribute: 'environment', route: '/v1/environments', type: 'image/png' },
};
// What the server does between the last byte received and its answer.
const SERVER_WORK = { mesh: 'Reading mesh…', environment: 'Preprocessing lights…' };
const pickers = { mesh: meshPicker, environment: environmentPicker };
// Per attribute, the pickers' options: the presets, then this page's uploads ({ id, name }).
const presets = { mesh: [], environment: [] };
const uploads = { mesh: [], environment: [] };

// A content id is 64 hexadecimal digits; its first 8 tell uploads apart. The mesh attribute
// may hold several ids, one object each.
const shortName = (value) =>
  value.split(/\s+/).filter(Boolean).map((id) => (/^[0-9a-f]{64}$/.test(id) ? id.slice(0, 8) : id))
    .join(' + ');
// A shared link's uploads, by the names it carries.
for (const attribute of ['mesh', 'environment']) {
  const name = initialQuery.get(`${attribute}-name`);
  if (name && viewer.hasAttribute(attribute)) {
    uploadNames[attribute].set(viewer.getAttribute(attribute), name);
    uploads[attribute].push({ id: viewer.getAttribute(attribute), name });
  }
}

const showPicked = (attribute) => {
  const picker = pickers[attribute];
  const current = viewer[attribute];  // 'default' when the attribute is absent
  const choices = [...presets[attribute], ...uploads[attribute]];
  if (!choices.some((choice) => choice.id === current)) {
    choices.push({ id: current, name: uploadNames[attribute].get(current) ?? shortName(current) });
  }
  picker.replaceChildren(...choices.map(({ id, name, description }) => {
    const option = new Option(name, id);
    option.title = description ?? id;
    return option;
  }));
  picker.value = current;
};
const showPickers = () => {
  showPicked('mesh');
  showPicked('environment');
};
showPickers();
new MutationObserver(showPickers)
  .observe(viewer, { attributes: true, attributeFilter: ['mesh', 'environment'] });

const show = (attribute, id) => {
  // The weights in `lights` belong to the previous environment's lights, in their order.
  if (attribute === 'environment') {
    viewer.removeAttribute('lights');
  }
  // An asset camera, a variant and a part belong to the previous product.
  if (attribute === 'mesh') {
    for (const name of ['camera-asset', 'variant', 'base-color-material']) {
      viewer.removeAttribute(name);
    }
  }
  viewer.setAttribute(attribute, id);
};
meshPicker.addEventListener('change', () => show('mesh', meshPicker.value));
environmentPicker.addEventListener('change', () => show('environment', environmentPicker.value));

const say = (text, { error = false } = {}) => {
  uploadStatus.textContent = text;
  uploadStatus.classList.toggle('error', error);
};

const fetchJson = async (path) => {
  const url = `${viewer.server}${path}`;
  const response = await fetch(url);
  if (!response.ok) {
    throw await problemOf(response, url);
  }
  return response.json();
};
fetchJson('/v1/presets').then((answer) => {
  presets.mesh = answer.meshes;
  presets.environment = answer.environments;
  showPickers();
}, (error) => say(`The presets did not load: ${error.message}`, { error: true }));
// The product's own cameras as views (its first mesh's `cameras`, GET /v1/meshes/{id}):
// "Orbit", then each perspective camera by name; an orthographic one is listed but disabled
// (the server draws perspective cameras only). Hidden for a product without cameras. A drag
// removes camera-asset, which sets the picker back to Orbit.
const viewGroup = document.getElementById('view-group');
const viewPicker = document.getElementById('view-picker');
// camera-asset holds an index (what the picker sets) or a name (a link may hold either).
const showView = () => {
  const asset = viewer.getAttribute('camera-asset') ?? '';
  const shown = [...viewPicker.options].find(
    (option) => option.value === asset || (asset !== '' && option.textContent === asset));
  viewPicker.value = shown?.value ?? '';
};
const showViews = (cameras) => {
  viewPicker.replaceChildren(new Option('Orbit', ''), ...cameras.map((camera) => {
    const option = new Option(camera.name, String(camera.index));
    option.disabled = camera.type !== 'perspective';
    if (option.disabled) {
      option.textContent += ' (orthographic: not drawn)';
    }
    return option;
  }));
  viewGroup.hidden = cameras.length === 0;
  showView();
};
// The product's own choices, from its first mesh's JSON (GET /v1/meshes/{id}): its cameras as
// views, its variants as swatches, its materials as the parts a color can go to.
let productFor = null;  // the mesh id they are of
const loadProduct = async () => {
  const mesh = viewer.mesh.split(/\s+/).find(Boolean) ?? 'default';
  if (mesh === productFor) {
    return;
  }
  productFor = mesh;
  let product = {};
  try {
    product = await fetchJson(`/v1/meshes/${encodeURIComponent(mesh)}`);
  } catch (error) {
    say(`The product's views, variants and parts did not load: ${error.message}`, { error: true });
  }
  if (mesh !== productFor) {
    return;  // another product was picked meanwhile
  }
  showViews(product.cameras ?? []);
  showProductVariants(product.variants ?? []);
  showParts(product.materials ?? []);
};
viewPicker.addEventListener('change', () => {
  if (viewPicker.value === '') {
    viewer.removeAttribute('camera-asset');
  } else {
    viewer.setAttribute('camera-asset', viewPicker.value);
  }
});
new MutationObserver(showView).observe(viewer, { attributeFilter: ['camera-asset'] });
new MutationObserver(loadProduct).observe(viewer, { attributeFilter: ['mesh'] });
loadProduct();

// The server's upload limit, to refuse a larger file before sending it; null when unknown
// (GET /v1/info failed, which the status says: the server's 413 then refuses it).
const uploadLimit = fetchJson('/v1/info').then(
  (info) => info.limits.max_upload_bytes,
  (error) => {
    say(`The server's limits did not load: ${error.message}`, { error: true });
    return null;
  });

const sizeText = (bytes) => {
  const mebibytes = bytes / 2 ** 20;
  const rounded = mebibytes >= 1 ? `${mebibytes.toFixed(1)} MiB`
    : `${(bytes / 1024).toFixed(1)} KiB`;
  return `${bytes.toLocaleString('en-US')} bytes (${rounded})`;
};

// The file being sent, one at a time. The button stays enabled meanwhile (disabling it would
// take the keyboard focus away); the group is aria-busy.
let uploading = null;
const refuseWhileUploading = (name) => {
  if (uploading) {
    say(`${name}: wait until ${uploading.name} is uploaded`, { error: true });
  }
  return uploading !== null;
};
const endUpload = () => {
  uploading = null;
  uploadGroup.removeAttribute('aria-busy');
};
// An uploaded mesh's first frames need its transfer (occlusion and one bounce), which the
// server starts baking on upload: GET /v1/meshes/{id}/preparation/events streams how far it
// has come (one event a change), followed into the progress bar until it is ready (or will not
// be prepared ahead); the bake without the floor, which the server streams after it, is not
// waited for. The status line, which a screen reader announces, changes only every 10 %.
// Rejects when the stream fails (the server gone, the mesh deleted meanwhile): EventSource
// says nothing of why, and would reconnect for ever.
function followPreparation(id, name) {
  const url = `${viewer.server}/v1/meshes/${encodeURIComponent(id)}/preparation/events`;
  return new Promise((resolve, reject) => {
    let announced = -1;
    const events = new EventSource(url);
    events.addEventListener('progress', (event) => {
      const preparation = JSON.parse(event.data);
      if (preparation.state !== 'queued' && preparation.state !== 'baking') {
        events.close();
        resolve();
        return;
      }
      const percent = Math.floor(100 * preparation.progress);
      if (preparation.state === 'queued' || percent === 0) {
        uploadProgress.removeAttribute('value');
      } else {
        uploadProgress.value = preparation.progress;
      }
      const step = Math.floor(percent / 10);
      if (step !== announced) {
        announced = step;
        const left = preparation.seconds_left === null ? ''
          : `, about ${Math.max(1, Math.round(preparation.seconds_left))} s left`;
        say(`Preparing ${name}'s shadows and reflected light: ${percent} %${left}`);
      }
    });
    events.addEventListener('error', () => {
      events.close();
      reject(new Error(`the stream ${url} broke off`));
    });
  });
}

// Resolves once the view shows `id` as its `attribute` (a frame of it, not a preliminary one),
// or once the view has moved on to another; rejects with the element's error meanwhile. Until
// then the upload is not "done": the previous product or environment is still on screen.
// Listening starts before the attribute is set, so that no frame is missed.
function shownInView(attribute, id) {
  const parameter = attribute === 'mesh' ? 'mesh' : 'environment';
  const holds = (value) => (value ?? '').split(/\s+/).includes(id);
  return new Promise((resolve, reject) => {
    const done = (settle, value) => {
      viewer.removeEventListener('load', onLoad);
      viewer.removeEventListener('error', onError);
      settle(value);
    };
    const onLoad = ({ detail }) => {
      const query = new URL(detail.url, location.href).searchParams;
      if (!holds(viewer.getAttribute(attribute))) {
        done(resolve);  // another was picked meanwhile
      } else if (!detail.preliminary && query.getAll(parameter).includes(id)) {
        done(resolve);
      }
    };
    const onError = ({ detail }) => done(reject, new Error(detail.message));
    viewer.addEventListener('load', onLoad);
    viewer.addEventListener('error', onError);
  });
}

const plural = (count, noun) => `${count.toLocaleString('en-US')} ${noun}${count === 1 ? '' : 's'}`;

async function upload(file) {
  if (refuseWhileUploading(file.name)) {
    return;
  }
  const extension = /\.([^.]+)$/.exec(file.name)?.[1].toLowerCase();
  const kind = UPLOAD_KINDS[extension];
  if (!kind) {
    say(`${file.name}: not a product (.glb, .gltf, .obj) or an environment ` +
        '(.hdr, .exr, .jpg, .png)', { error: true });
    return;
  }
  uploading = file;
  uploadGroup.setAttribute('aria-busy', 'true');
  const limit = await uploadLimit;
  if (limit !== null && file.size > limit) {
    say(`${file.name} is ${sizeText(file.size)}, over the server's upload limit of ` +
        `${sizeText(limit)}`, { error: true });
    endUpload();
    return;
  }
  // The file's own name goes with it, so that the server's errors name it.
  const url = `${viewer.server}${kind.route}?filename=${encodeURIComponent(file.name)}`;
  const request = new XMLHttpRequest();
  const finish = (text, options) => {
    say(text, options);
    uploadProgress.hidden = true;
    endUpload();
  };
  // The bar follows every byte; the status (announced) every 10 %.
  let announcedTenth = 0;
  request.upload.addEventListener('progress', (event) => {
    if (event.lengthComputable) {
      uploadProgress.value = event.loaded / event.total;
      const percent = Math.round((100 * event.loaded) / event.total);
      if (Math.floor(percent / 10) !== announcedTenth) {
        announcedTenth = Math.floor(percent / 10);
        say(`Uploading ${file.name}: ${percent} %`);
      }
    }
  });
  // Every byte is sent; the answer comes once the server has read the file (an environment's
  // preprocessing takes seconds for a big map). A progress without a value is indeterminate.
  request.upload.addEventListener('load', () => {
    uploadProgress.removeAttribute('value');
    say(SERVER_WORK[kind.attribute]);
  });
  request.addEventListener('load', async () => {
    if (request.status < 200 || request.status >= 300) {
      // problemOf reads a fetch Response; this one holds the XMLHttpRequest's answer.
      const answer = new Response(request.responseText,
                                  { status: request.status, statusText: request.statusText });
      const problem = await problemOf(answer, url);
      finish(problem.message, { error: true });
      return;
    }
    let asset;
    try {
      asset = JSON.parse(request.responseText);
    } catch (error) {
      finish(`${file.name}: the answer of ${url} is not JSON (${error.message})`, { error: true });
      return;
    }
    if (!uploads[kind.attribute].some((choice) => choice.id === asset.id)) {
      uploads[kind.attribute].push({ id: asset.id, name: file.name });
    }
    uploadNames[kind.attribute].set(asset.id, file.name);
    // Listening before the view changes; the same file again leaves the view as it is.
    const alreadyShown = viewer.getAttribute(kind.attribute) === asset.id;
    const shown = alreadyShown ? Promise.resolve() : shownInView(kind.attribute, asset.id);
    let onScreen = alreadyShown;
    shown.then(() => { onScreen = true; }, () => {});  // a failure is handled below
    show(kind.attribute, asset.id);
    writeLink();  // the name too, even when the id was already the view's
    const summary = kind.attribute === 'environment'
      ? `${file.name}: ${plural(asset.lights.length, 'light')}`
      : `${file.name}: ${plural(asset.counts.triangles, 'triangle')}`;
    try {
      if (kind.attribute === 'mesh') {
        await followPreparation(asset.id, file.name);
      }
    } catch (error) {
      finish(`${summary}; its preparation's progress did not load: ${error.message}`,
             { error: true });
      return;
    }
    // Prepared; "done" only once it is on screen.
    if (!onScreen) {
      uploadProgress.removeAttribute('value');
      say(`Showing ${file.name}…`);
    }
    try {
      await shown;
      finish(summary);
    } catch (error) {
      finish(`${file.name} was uploaded but cannot be shown: ${error.message}`, { error: true });
    }
  });
  request.addEventListener('error', () =>
    finish(`Network error: ${file.name} did not reach ${new URL(url, location.href).origin}`,
           { error: true }));
  request.open('POST', url);
  request.setRequestHeader('Content-Type', kind.type);
  uploadProgress.value = 0;
  uploadProgress.hidden = false;
  say(`Uploading ${file.name}: 0 %`);
  request.send(file);
}

uploadButton.addEventListener('click', () => {
  if (!refuseWhileUploading('Another file')) {
    uploadFile.click();
  }
});
uploadFile.addEventListener('change', () => {
  const [file] = uploadFile.files;
  // Cleared, so that choosing the same file again (after fixing it, say) is a change too.
  uploadFile.value = '';
  if (file) {
    upload(file);
  }
});

// A file dragged over the page shows the hint until it leaves the window or is dropped;
// dragenter and dragleave come for every element crossed, hence the count.
let dragDepth = 0;
const carriesFiles = (event) => event.dataTransfer?.types.includes('Files');
document.addEventListener('dragenter', (event) => {
  if (carriesFiles(event)) {
    event.preventDefault();
    dragDepth += 1;
    dropHint.hidden = false;
  }
});
document.addEventListener('dragover', (event) => {
  if (carriesFiles(event)) {
    event.preventDefault();  // lets the drop happen
    event.dataTransfer.dropEffect = 'copy';
  }
});
document.addEventListener('dragleave', (event) => {
  if (carriesFiles(event)) {
    dragDepth = Math.max(0, dragDepth - 1);
    dropHint.hidden = dragDepth > 0;
  }
});
document.addEventListener('drop', (event) => {
  if (!carriesFiles(event)) {
    return;
  }
  event.preventDefault();  // the browser would open the file instead
  dragDepth = 0;
  dropHint.hidden = true;
  const files = [...event.dataTransfer.files];
  if (files.length === 1) {
    upload(files[0]);
  } else {
    say(`Drop one file at a time (${files.length} were dropped)`, { error: true });
  }
});

// Image sets, made by the server as batch jobs (POST /v1/jobs, docs/jobs.md): "Spin set", a
// turntable of the view (Views around its orbit), and "All variants", the view in each of the
// product's variants; each image Size×Size, otherwise the view's own request (its environment,
// objects, variant, colors, lights, ground, camera). One job at a time. Its event stream
// (GET /v1/jobs/{id}/events) moves the progress bar and the text beside it, which are not
// announced; the status line announces the settled states only (started, done, failed,
// cancelled). Once done the page offers links to what the job made, which the user clicks to
// save. The page sends no API key (it has none, as for uploads): a server with one refuses it.
const jobViews = document.getElementById('job-views');
const jobSize = document.getElementById('job-size');
const spinSetButton = document.getElementById('spin-set');
const jobProgressGroup = document.getElementById('job-progress-group');
const jobProgress = document.getElementById('job-progress');
const jobProgressText = document.getElementById('job-progress-text');
const jobCancel = document.getElementById('job-cancel');
const jobResults = document.getElementById('job-results');
const JOB_KINDS = {
  spin: { title: 'Spin set', what: 'the spin set', noun: 'view', file: 'spin-set' },
  variants: { title: 'All variants', what: 'the variants\' images', noun: 'variant', file: 'variants' },
};
const SETTLED_STATES = new Set(['done', 'failed', 'cancelled']);
// A stream that breaks off while its job goes on is opened again this many times in a row,
// this long after the break, before the page gives up on following the job.
const JOB_STREAM_RETRIES = 3;
const JOB_STREAM_RETRY_MS = 1000;
// The job being made: { kind, button (the one that started it), id, format, events,
// retries }; null when none.
let currentJob = null;

// A refused job request in plain words: `failed` says what failed ("The spin set could not
// be started"), then why, with the server's own detail where it says what to change.
async function jobRefusal(response, url, failed) {
  const retryAfter = response.headers.get('Retry-After');
  const again = `Try again ${retryAfter ? `in ${retryAfter} s` : 'in a moment'}.`;
  const { message, type } = await problemOf(response, url);
  switch (response.status) {
    case 401:
      return `${failed}: the server asks for a key that this page does not have.`;
    case 413:
      return `${failed}: it is more than the server makes in one job. Choose fewer views or a ` +
        `smaller size (${message}).`;
    case 429:
      // The client's unfinished jobs are at their bounds (too-many-renders), or its address
      // holds too many connections.
      return type === '/v1/problems/too-many-renders'
        ? `${failed}: the server is still making your earlier images. ${again}`
        : `${failed}: the server is busy. ${again}`;
    case 503:
      return `${failed}: the server is busy. ${again}`;
    default:
      return `${failed}: ${message}`;
  }
}

const showJobProgress = (kind, { state, done, failed, total, seconds_left: secondsLeft }) => {
  const { noun } = JOB_KINDS[kind];
  jobProgress.value = total > 0 ? (done + failed) / total : 0;
  const parts = [`${done}/${plural(total, noun)}`];
  if (failed > 0) {
    parts.push(`${failed} failed`);
  }
  if (secondsLeft !== null && secondsLeft !== undefined) {
    parts.push(`about ${Math.max(1, Math.ceil(secondsLeft))} s left`);
  }
  if (state === 'done' || state === 'cancelled') {
    parts.push(state);
  }
  jobProgressText.textContent = parts.join(', ');
};

// A link the user clicks to save what `href` answers as `fileName`.
const downloadLink = (href, fileName, ...content) => {
  const link = document.createElement('a');
  link.href = href;
  link.download = fileName;
  link.append(...content);
  return link;
};
const FILE_EXTENSIONS = { jpeg: 'jpg', png: 'png' };

// The links to what a done job made: a spin set's animated WebP, sprite sheet (in its frames'
// format: PNG keeps a transparent background) and ZIP; the variants' ZIP and each variant's
// image, shown small.
function jobLinks(job, status) {
  const base = `${viewer.server}/v1/jobs/${job.id}`;
  const file = `${JOB_KINDS[job.kind].file}-${job.id.slice(0, 8)}`;
  const extension = FILE_EXTENSIONS[job.format];
  const zip = downloadLink(`${base}/zip`, `${file}.zip`, `ZIP (${plural(status.done, 'image')})`);
  if (job.kind === 'spin') {
    const sequence = `${base}/sequences/${encodeURIComponent(status.sequences[0])}`;
    return [downloadLink(sequence, `${file}.webp`, 'Animated WebP'),
            downloadLink(`${sequence}?format=${job.format}`, `${file}-sprites.${extension}`,
                         'Sprite sheet'),
            zip];
  }
  return [zip, ...job.frames.map(({ name, variant }) => {
    const href = `${base}/frames/${encodeURIComponent(name)}`;
    const thumbnail = document.createElement('img');
    thumbnail.src = href;
    thumbnail.alt = '';  // the link's text names it
    return downloadLink(href, `${file}-${name}.${extension}`, thumbnail, variant);
  })];
}

// Why a failed job's first failed frame failed, as the job's status names it.
async function firstFailure(id) {
  try {
    const { frames } = await fetchJson(`/v1/jobs/${id}`);
    const frame = frames.find((candidate) => candidate.state === 'failed');
    return frame ? `${frame.name}: ${frame.error}` : 'the server did not say why';
  } catch (error) {
    return `why did not load: ${error.message}`;
  }
}

async function settleJob(job, status) {
  if (currentJob !== job) {
    return;  // settled already (the cancellation's answer and the stream both say so)
  }
  currentJob = null;
  job.events?.close();
  showJobProgress(job.kind, status);
  // Cancel goes; the keyboard's focus, if it was there, goes back to the job's button.
  const cancelFocused = document.activeElement === jobCancel;
  jobCancel.hidden = true;
  if (cancelFocused) {
    job.button.focus();
  }
  const { title, noun } = JOB_KINDS[job.kind];
  if (status.state === 'done') {
    jobResults.replaceChildren(...jobLinks(job, status));
    setStatus(`${title} ready: ${plural(status.done, noun)}; save them with the links beside it.`);
  } else if (status.state === 'cancelled') {
    setStatus(`${title} cancelled after ${status.done} of ${plural(status.total, noun)}.`);
  } else {
    setStatus(`${title} failed: ${status.failed} of ${plural(status.total, noun)} could not be ` +
              `made (${await firstFailure(job.id)}).`, { error: true });
  }
}

// Gives up on a job the page can no longer follow; the server may still make it.
function loseJob(job, text) {
  if (currentJob === job) {
    currentJob = null;
    job.events?.close();
    jobCancel.hidden = true;
    setStatus(text, { error: true });
  }
}

// Follows the job's events; a stream that breaks off before the job settles (the network, a
// restarted server) is opened again while the job's status still answers.
function followJob(job) {
  const events = new EventSource(`${viewer.server}/v1/jobs/${job.id}/events`);
  job.events = events;
  events.addEventListener('progress', (event) => {
    if (currentJob !== job) {
      return;
    }
    job.retries = 0;
    const status = JSON.parse(event.data);
    showJobProgress(job.kind, status);
    if (SETTLED_STATES.has(status.state)) {
      settleJob(job, status);
    }
  });
  events.addEventListener('error', async () => {
    events.close();  // else it retries on its own, forever
    if (currentJob !== job) {
      return;
    }
    const { title } = JOB_KINDS[job.kind];
    let status;
    try {
      status = await fetchJson(`/v1/jobs/${job.id}`);
    } catch (error) {
      loseJob(job, error.status
        ? `${title} stopped: ${error.message}`
        : `Network error: the server stopped answering about the ${title.toLowerCase()} ` +
          '(it may still be making it).');
      return;
    }
    if (SETTLED_STATES.has(status.state)) {
      settleJob(job, status);
    } else if (job.retries < JOB_STREAM_RETRIES) {
      job.retries += 1;
      setTimeout(() => {
        if (currentJob === job) {
          followJob(job);
        }
      }, JOB_STREAM_RETRY_MS);
    } else {
      loseJob(job, `${title}: its progress stopped coming; it may still be made.`);
    }
  });
}

// Asks for the job `body` (POST /v1/jobs) and follows it. `details` go with the job's record
// (its frames' names, its images' format) for the links once done.
async function startJob(kind, button, body, details) {
  const { title, what, noun } = JOB_KINDS[kind];
  if (currentJob) {
    setStatus(`Wait until ${JOB_KINDS[currentJob.kind].what} is made, or cancel it.`, { error: true });
    return;
  }
  const job = { kind, button, id: null, events: null, retries: 0, ...details };
  currentJob = job;
  jobResults.replaceChildren();
  const url = `${viewer.server}/v1/jobs`;
  let status;
  try {
    const response = await fetch(url, { method: 'POST', headers: { 'Content-Type': 'application/json' },
                                        body: JSON.stringify(body) });
    if (!response.ok) {
      currentJob = null;
      setStatus(await jobRefusal(response, url, `${title} could not be started`), { error: true });
      return;
    }
    status = await response.json();
  } catch {
    currentJob = null;
    setStatus(`Network error: ${what} could not be asked of the server ` +
              `(${new URL(url, location.href).origin}).`, { error: true });
    return;
  }
  job.id = status.id;
  jobProgress.setAttribute('aria-label', `${title} progress`);
  jobProgressGroup.hidden = false;
  jobCancel.hidden = false;
  showJobProgress(kind, status);
  setStatus(`Making ${what}: ${plural(status.total, noun)}…`);
  followJob(job);
}

// Cancel: DELETE /v1/jobs/{id}; its answer is the cancelled job's status.
jobCancel.addEventListener('click', async () => {
  const job = currentJob;
  if (!job?.id) {
    return;
  }
  const url = `${viewer.server}/v1/jobs/${job.id}`;
  const { title } = JOB_KINDS[job.kind];
  try {
    const response = await fetch(url, { method: 'DELETE' });
    if (!response.ok) {
      setStatus(await jobRefusal(response, url, `${title} could not be cancelled`), { error: true });
      return;
    }
    settleJob(job, await response.json());
  } catch {
    setStatus(`Network error: the cancellation of the ${title.toLowerCase()} did not reach the server.`,
              { error: true });
  }
});

// The images' side, from the Size picker.
const jobImageSize = () => Number(jobSize.value);

spinSetButton.addEventListener('click', () => {
  const views = jobViews.valueAsNumber;
  if (!Number.isInteger(views) || !jobViews.checkValidity()) {
    setStatus(`Views: a whole number from ${jobViews.min} to ${jobViews.max}.`, { error: true });
    return;
  }
  const size = jobImageSize();
  const render = { ...viewer.renderRequest({ assetCamera: false }), width: size, height: size };
  startJob('spin', spinSetButton, { turntable: { render, views } },
           { format: render.format ?? 'jpeg' });
});

// A variant's frame name: its place and its name in the characters a job's frame name takes
// (api/openapi.yaml, JobRequest), unique by the place.
const variantFrameName = (variant, index) =>
  `${String(index + 1).padStart(2, '0')}-${variant.replace(/[^A-Za-z0-9._-]+/g, '_').slice(0, 90)}`;

allVariantsButton.addEventListener('click', () => {
  const size = jobImageSize();
  const render = { ...viewer.renderRequest(), width: size, height: size };
  const frames = productVariantNames.map((variant, index) => ({
    name: variantFrameName(variant, index),
    variant,
    render: { ...render, objects: render.objects.map((object) => ({ ...object, variant })) },
  }));
  startJob('variants', allVariantsButton,
           { frames: frames.map(({ name, render: frame }) => ({ name, render: frame })) },
           { format: render.format ?? 'jpeg', frames });
});

// Last, what the link carries besides the element's attributes: its hotspots.
restoreLinkHotspots();
