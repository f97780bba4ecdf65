// The page at /: the controls of the view around one <oer-viewer> (index.html).
import { equirectangularUv } from '/web/oer-viewer.js';

// The page's view state lives in the element's attributes and, mirrored, in the URL's
// query, so that a shared link reproduces the same frame (the same ETag).
const viewer = document.getElementById('viewer');
// stateAttributes: declared by index.html's inline script, which applies the URL's query.

const exposure = document.getElementById('exposure');
const exposureValue = document.getElementById('exposure-value');
const background = document.getElementById('background');
const backgroundColor = document.getElementById('background-color');
const ground = document.getElementById('ground');
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
  ground.checked = viewer.getAttribute('ground') !== 'off';
  environmentYaw.value = viewer.getAttribute('environment-yaw') ?? '0';
  environmentYawValue.value = environmentYaw.value;
};
showState();

new MutationObserver(() => {
  const next = new URLSearchParams();
  for (const name of stateAttributes) {
    const value = viewer.getAttribute(name);
    if (value !== null && value !== '') {
      next.set(name, value);
    }
  }
  const text = next.toString();
  history.replaceState(null, '', text ? `?${text}` : location.pathname);
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
ground.addEventListener('change', () => {
  if (ground.checked) {
    viewer.removeAttribute('ground');
  } else {
    viewer.setAttribute('ground', 'off');
  }
});
environmentYaw.addEventListener('input', () => {
  environmentYawValue.value = environmentYaw.value;
  viewer.adjust('environment-yaw', Number(environmentYaw.value) === 0 ? null : environmentYaw.value);
});

// The turntable is behaviour, not view state: not in the URL.
const turntable = document.getElementById('turntable');
turntable.addEventListener('change', () => viewer.toggleAttribute('auto-rotate', turntable.checked));

// Color variants: base-color as #rrggbb (sRGB), absent for the product's own materials.
const variants = [...document.querySelectorAll('input[name=variant]')];
const showVariant = () => {
  const value = (viewer.getAttribute('base-color') ?? '').toLowerCase();
  for (const variant of variants) {
    variant.checked = variant.value === value;
  }
};
for (const variant of variants) {
  variant.addEventListener('change', () => {
    if (variant.value) {
      viewer.setAttribute('base-color', variant.value);
    } else {
      viewer.removeAttribute('base-color');
    }
  });
}
showVariant();
new MutationObserver(showVariant).observe(viewer, { attributeFilter: ['base-color'] });

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
const showLights = ({ lights, weights }) => {
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
viewer.addEventListener('lights-change', ({ detail }) => showLights(detail));
// The element may have its lights before this module listens (its request can end first).
if (viewer.lights.length > 0) {
  showLights({ lights: viewer.lights, weights: viewer.lights.map((light) => light.weight) });
}
document.getElementById('all-on').addEventListener('click', () => viewer.removeAttribute('lights'));
document.getElementById('all-off').addEventListener('click', () =>
  viewer.setAttribute('lights', viewer.lights.map(() => 0).join(',')));

// The status line: size, bytes, time in the browser and on the server (or that the server's
// cache answered), and while dragging the previews shown per second since the press.
const status = document.getElementById('status');
let drag = { started: 0, previews: 0 };
viewer.addEventListener('pointerdown', () => { drag = { started: performance.now(), previews: 0 }; });
viewer.addEventListener('load', ({ detail }) => {
  // Server-Timing lists the passes, their `total`, then `encode` (server/README.md); a frame
  // from the server's cache has none.
  const timing = Object.fromEntries((detail.serverTiming ?? '').split(',').map((entry) => {
    const [name, ...fields] = entry.trim().split(';');
    const duration = fields.find((field) => field.startsWith('dur='));
    return [name, Number(duration?.slice(4) ?? 0)];
  }));
  const server = (timing.total ?? 0) + (timing.encode ?? 0);
  const parts = [
    `${detail.width}×${detail.height}${detail.stage === 'full' ? '' : ` ${detail.stage}`}`,
    `${(detail.bytes / 1024).toFixed(0)} KiB`,
    `${detail.milliseconds.toFixed(0)} ms`,
    detail.cache === 'hit' ? 'cached' : `server ${server.toFixed(0)} ms`,
  ];
  if (detail.stage === 'preview' && viewer.hasAttribute('dragging')) {
    drag.previews += 1;
    const seconds = (performance.now() - drag.started) / 1000;
    parts.push(`${(drag.previews / seconds).toFixed(1)} fps`);
  }
  status.textContent = parts.join(', ');
  status.classList.remove('error');
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
    status.textContent = error.message;
    status.classList.add('error');
  } finally {
    download.disabled = false;
  }
});

viewer.addEventListener('error', ({ detail }) => {
  status.textContent = detail.detail;
  status.classList.add('error');
});
