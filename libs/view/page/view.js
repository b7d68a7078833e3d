// facetool view: the page's script: layers with a wipe, hover read-outs, and each face relit per
// pixel in WebGL2 with the sh_renderer's triple product and relight's paste-back (docs/viewer.md).
'use strict';
(function () {
const data = JSON.parse(document.getElementById('facetool-data').textContent);
const $ = (id) => document.getElementById(id);
const errors = [];
window.addEventListener('error', (e) => errors.push(String(e.message)));
const SQRT_PI = Math.sqrt(Math.PI);

// Real SH of degree <= 2 at a unit direction (docs/conventions.md).
function shBasis(x, y, z) {
  return [0.282094791773878143, 0.488602511902919922 * y, 0.488602511902919922 * z, 0.488602511902919922 * x,
    1.09254843059207907 * x * y, 1.09254843059207907 * y * z, 0.315391565252520006 * (3 * z * z - 1),
    1.09254843059207907 * x * z, 0.546274215296039535 * (x * x - y * y)];
}
const BAND_FACTOR = [Math.PI, 2 * Math.PI / 3, 2 * Math.PI / 3, 2 * Math.PI / 3, Math.PI / 4, Math.PI / 4,
  Math.PI / 4, Math.PI / 4, Math.PI / 4];

// A distant light plus ambient from degrees, as `facetool light from-direction` (each channel
// scaled by the colour): pi * intensity * Y(d), and sqrt(4 pi) * ambient on coefficient 0.
function directionalLight(azimuth, elevation, ambient, intensity, colour) {
  const a = azimuth * Math.PI / 180, e = elevation * Math.PI / 180;
  const y = shBasis(Math.sin(a) * Math.cos(e), Math.sin(e), Math.cos(a) * Math.cos(e));
  const light = new Array(27);
  for (let c = 0; c < 3; ++c) {
    for (let i = 0; i < 9; ++i) light[c * 9 + i] = Math.PI * intensity * colour[c] * y[i];
    light[c * 9] += Math.sqrt(4 * Math.PI) * ambient * colour[c];
  }
  return light;
}

function srgbToLinear(v) { return v <= 0.04045 ? v / 12.92 : Math.pow((v + 0.055) / 1.055, 2.4); }
function linearToSrgb(v) {
  const x = Math.min(Math.max(v, 0), 1);
  return x <= 0.0031308 ? 12.92 * x : 1.055 * Math.pow(x, 1 / 2.4) - 0.055;
}

// Each face's packed crop layers as float planes: normal xyz, visibility 0..8, albedo rgb, shading rgb.
function unpackFace(face) {
  const s = face.crop_size, plane = s * s, bytes = atob(face.planes);
  const planes = [];
  for (let c = 0; c < 18; ++c) {
    const lo = face.ranges[2 * c], step = (face.ranges[2 * c + 1] - lo) / 65535, out = new Float32Array(plane);
    for (let i = 0; i < plane; ++i) {
      const at = 2 * (c * plane + i);
      out[i] = lo + (bytes.charCodeAt(at) | (bytes.charCodeAt(at + 1) << 8)) * step;
    }
    planes.push(out);
  }
  return planes;
}

function loadImage(url) {
  return new Promise((resolve, reject) => {
    const img = new Image();
    img.onload = () => resolve(img);
    img.onerror = () => reject(new Error('an embedded image does not decode'));
    img.src = url;
  });
}

// Where photo pixel (x, y) falls in face k's crop, and its paste-back weight (paste_back.cpp).
function cropPosition(face, x, y) {
  const [a, b, tx, ty] = face.photo_to_crop;
  const cx = a * x - b * y + tx, cy = b * x + a * y + ty;
  let depth = Infinity;
  for (let e = 0; e < face.mask_lines.length; e += 1) {
    const l = face.mask_lines[e], side = l[0] * cx + l[1] * cy + l[2];
    if (side <= 0) return { cx, cy, alpha: 0 };
    depth = Math.min(depth, side);
  }
  return { cx, cy, alpha: data.feather > 0 ? Math.min(1, depth / data.feather) : 1 };
}

// ---- WebGL2: per face a crop pass (the renderer), then one paste pass at the photo's size ----
const VERTEX = `#version 300 es
in vec2 corner; void main() { gl_Position = vec4(corner, 0.0, 1.0); }`;

// The sh_renderer's forward pass at one crop pixel (kernels/sh_render.cl): the normal normalised
// (shorter than 1e-8 renders 0), e_i = sum T_ijk v_j c_k(n), shading = 1/pi sum_i L_i e_i.
function cropShader(triple) {
  const terms = [];
  for (const [i, j, k, t] of triple) terms.push(`  e[${i}] += ${glFloat(t)} * v[${j}] * c[${k}];`);
  return `#version 300 es
precision highp float; precision highp int; precision highp sampler2D;
uniform sampler2D u_in; uniform int u_size; uniform float u_light[27]; uniform int u_render; uniform int u_visibility;
out vec4 o;
void main() {
  ivec2 q = ivec2(gl_FragCoord.xy);
  vec4 t0 = texelFetch(u_in, q, 0), t1 = texelFetch(u_in, q + ivec2(0, u_size), 0);
  vec4 t2 = texelFetch(u_in, q + ivec2(0, 2 * u_size), 0), t3 = texelFetch(u_in, q + ivec2(0, 3 * u_size), 0);
  float len = sqrt(t0.x * t0.x + t0.y * t0.y + t0.z * t0.z);
  if (!(len >= 1e-8)) { o = vec4(0.0); return; }
  float x = t0.x / len, y = t0.y / len, z = t0.z / len;
  float c[9], v[9], e[9];
  c[0] = 3.14159265358979323846 * 0.282094791773878143;
  c[1] = 2.09439510239319549 * 0.488602511902919922 * y;
  c[2] = 2.09439510239319549 * 0.488602511902919922 * z;
  c[3] = 2.09439510239319549 * 0.488602511902919922 * x;
  c[4] = 0.785398163397448310 * 1.09254843059207907 * x * y;
  c[5] = 0.785398163397448310 * 1.09254843059207907 * y * z;
  c[6] = 0.785398163397448310 * 0.315391565252520006 * (3.0 * z * z - 1.0);
  c[7] = 0.785398163397448310 * 1.09254843059207907 * x * z;
  c[8] = 0.785398163397448310 * 0.546274215296039535 * (x * x - y * y);
  if (u_visibility == 1) {
    v[0] = t1.x; v[1] = t1.y; v[2] = t1.z; v[3] = t1.w; v[4] = t2.x; v[5] = t2.y; v[6] = t2.z; v[7] = t2.w; v[8] = t3.x;
  } else {
    v[0] = 2.0 * 1.7724538509055160; for (int j = 1; j < 9; ++j) v[j] = 0.0;
  }
  for (int i = 0; i < 9; ++i) e[i] = 0.0;
${terms.join('\n')}
  vec3 s = vec3(0.0);
  for (int i = 0; i < 9; ++i) { s.r += u_light[i] * e[i]; s.g += u_light[9 + i] * e[i]; s.b += u_light[18 + i] * e[i]; }
  s *= 0.318309886183790672;
  vec3 albedo = vec3(t0.w, t3.y, t3.z);
  o = vec4(u_render == 1 ? albedo * s : s, 1.0);
}`;
}

function glFloat(value) {
  const text = String(value);
  return /[.eE]/.test(text) ? text : text + '.0';
}

// relight's paste-back (paste_back.cpp) of every face, in order, at one photo pixel, then the
// mode's last step: 0 the pasted value as it is, 1 sRGB-encoded, 2 photo x guarded ratio to u_old.
function pasteShader(faces, maxLines) {
  let samplers = '', calls = '';
  faces.forEach((face, k) => {
    samplers += `uniform sampler2D u_crop${k};\n`;
    calls += `  acc = pasteFace(u_crop${k}, ${k}, p, acc);\n`;
  });
  return `#version 300 es
precision highp float; precision highp int; precision highp sampler2D;
${samplers}uniform sampler2D u_photo; uniform sampler2D u_old; uniform sampler2D u_lines;
uniform vec4 u_t[${faces.length}]; uniform int u_crop_size[${faces.length}]; uniform int u_line_count[${faces.length}];
uniform float u_feather; uniform float u_epsilon; uniform int u_height; uniform int u_base; uniform int u_out;
out vec4 o;
float toLinear(float v) { return v <= 0.04045 ? v / 12.92 : pow((v + 0.055) / 1.055, 2.4); }
float toSrgb(float v) { float x = clamp(v, 0.0, 1.0); return x <= 0.0031308 ? 12.92 * x : 1.055 * pow(x, 1.0 / 2.4) - 0.055; }
vec3 pasteFace(sampler2D crop, int k, vec2 p, vec3 acc) {
  vec4 t = u_t[k];
  vec2 c = vec2(t.x * p.x - t.y * p.y + t.z, t.y * p.x + t.x * p.y + t.w);
  float depth = 1e30;
  for (int e = 0; e < ${maxLines}; ++e) {
    if (e >= u_line_count[k]) break;
    vec3 l = texelFetch(u_lines, ivec2(e, k), 0).xyz;
    float side = l.x * c.x + l.y * c.y + l.z;
    if (side <= 0.0) return acc;
    depth = min(depth, side);
  }
  float a = u_feather > 0.0 ? clamp(depth / u_feather, 0.0, 1.0) : 1.0;
  int s = u_crop_size[k];
  float cx = clamp(c.x, 0.0, float(s - 1)), cy = clamp(c.y, 0.0, float(s - 1));
  int x0 = min(int(cx), s - 1), y0 = min(int(cy), s - 1);
  int x1 = x0 + 1 < s ? x0 + 1 : x0, y1 = y0 + 1 < s ? y0 + 1 : y0;
  float fx = cx - float(x0), fy = cy - float(y0);
  vec3 q00 = texelFetch(crop, ivec2(x0, y0), 0).rgb, q10 = texelFetch(crop, ivec2(x1, y0), 0).rgb;
  vec3 q01 = texelFetch(crop, ivec2(x0, y1), 0).rgb, q11 = texelFetch(crop, ivec2(x1, y1), 0).rgb;
  vec3 v = (q00 * (1.0 - fx) + q10 * fx) * (1.0 - fy) + (q01 * (1.0 - fx) + q11 * fx) * fy;
  return a * v + (1.0 - a) * acc;
}
void main() {
  ivec2 pi = ivec2(int(gl_FragCoord.x), u_height - 1 - int(gl_FragCoord.y));
  vec2 p = vec2(pi);
  vec3 s = texelFetch(u_photo, pi, 0).rgb;
  vec3 photo = vec3(toLinear(s.r), toLinear(s.g), toLinear(s.b));
  vec3 acc = u_base == 0 ? photo : vec3(1.0);
${calls}  if (u_out == 0) { o = vec4(acc, 1.0); return; }
  vec3 result = acc;
  if (u_out == 2) {
    // u_old was drawn by this shader too: its rows are the framebuffer's (bottom up).
    vec3 old = texelFetch(u_old, ivec2(gl_FragCoord.xy), 0).rgb;
    result = photo * ((max(acc, 0.0) + u_epsilon) / (max(old, 0.0) + u_epsilon));
  }
  o = vec4(toSrgb(result.r), toSrgb(result.g), toSrgb(result.b), 1.0);
}`;
}

function compile(gl, vertex, fragment) {
  const program = gl.createProgram();
  for (const [type, source] of [[gl.VERTEX_SHADER, vertex], [gl.FRAGMENT_SHADER, fragment]]) {
    const shader = gl.createShader(type);
    gl.shaderSource(shader, source);
    gl.compileShader(shader);
    if (!gl.getShaderParameter(shader, gl.COMPILE_STATUS)) throw new Error('shader: ' + gl.getShaderInfoLog(shader));
    gl.attachShader(program, shader);
  }
  gl.bindAttribLocation(program, 0, 'corner');
  gl.linkProgram(program);
  if (!gl.getProgramParameter(program, gl.LINK_STATUS)) throw new Error('shader link: ' + gl.getProgramInfoLog(program));
  return program;
}

function floatTexture(gl, width, height, pixels) {
  const texture = gl.createTexture();
  gl.bindTexture(gl.TEXTURE_2D, texture);
  gl.texImage2D(gl.TEXTURE_2D, 0, gl.RGBA32F, width, height, 0, gl.RGBA, gl.FLOAT, pixels);
  for (const p of [gl.TEXTURE_MIN_FILTER, gl.TEXTURE_MAG_FILTER]) gl.texParameteri(gl.TEXTURE_2D, p, gl.NEAREST);
  for (const p of [gl.TEXTURE_WRAP_S, gl.TEXTURE_WRAP_T]) gl.texParameteri(gl.TEXTURE_2D, p, gl.CLAMP_TO_EDGE);
  return texture;
}

class Relighter {
  constructor(canvas, photoImage, faces, planes) {
    const gl = canvas.getContext('webgl2', { preserveDrawingBuffer: true, antialias: false, premultipliedAlpha: false });
    if (!gl) throw new Error('this browser has no WebGL2; the layers are shown, the relighting is not');
    if (!gl.getExtension('EXT_color_buffer_float')) throw new Error('this browser cannot render to float textures (EXT_color_buffer_float)');
    this.gl = gl;
    this.w = canvas.width = data.width;
    this.h = canvas.height = data.height;
    this.faces = faces;
    const buffer = gl.createBuffer();
    gl.bindBuffer(gl.ARRAY_BUFFER, buffer);
    gl.bufferData(gl.ARRAY_BUFFER, new Float32Array([-1, -1, 3, -1, -1, 3]), gl.STATIC_DRAW);
    gl.enableVertexAttribArray(0);
    gl.vertexAttribPointer(0, 2, gl.FLOAT, false, 0, 0);
    this.crop = compile(gl, VERTEX, cropShader(data.triple));
    const maxLines = Math.max(...faces.map((f) => f.mask_lines.length));
    this.paste = compile(gl, VERTEX, pasteShader(faces, maxLines));

    gl.pixelStorei(gl.UNPACK_COLORSPACE_CONVERSION_WEBGL, gl.NONE);
    gl.pixelStorei(gl.UNPACK_PREMULTIPLY_ALPHA_WEBGL, false);
    this.photo = gl.createTexture();
    gl.bindTexture(gl.TEXTURE_2D, this.photo);
    gl.texImage2D(gl.TEXTURE_2D, 0, gl.RGBA8, gl.RGBA, gl.UNSIGNED_BYTE, photoImage);
    for (const p of [gl.TEXTURE_MIN_FILTER, gl.TEXTURE_MAG_FILTER]) gl.texParameteri(gl.TEXTURE_2D, p, gl.NEAREST);
    const lines = new Float32Array(maxLines * faces.length * 4);
    faces.forEach((f, k) => f.mask_lines.forEach((l, e) => lines.set([l[0], l[1], l[2], 1], 4 * (k * maxLines + e))));
    this.lines = floatTexture(gl, maxLines, faces.length, lines);

    this.inputs = [];
    this.outputs = [];
    this.olds = [];
    faces.forEach((face, k) => {
      const s = face.crop_size, plane = s * s, p = planes[k];
      const packed = new Float32Array(plane * 16), old = new Float32Array(plane * 4);
      const tiles = [[0, 1, 2, 12], [3, 4, 5, 6], [7, 8, 9, 10], [11, 13, 14, -1]];
      tiles.forEach((tile, t) => tile.forEach((c, slot) => {
        if (c < 0) return;
        for (let i = 0; i < plane; ++i) packed[4 * (t * plane + i) + slot] = p[c][i];
      }));
      for (let i = 0; i < plane; ++i) old.set([p[15][i], p[16][i], p[17][i], 1], 4 * i);
      this.inputs.push(floatTexture(gl, s, 4 * s, packed));
      this.olds.push(floatTexture(gl, s, s, old));
      const target = floatTexture(gl, s, s, null), fbo = gl.createFramebuffer();
      gl.bindFramebuffer(gl.FRAMEBUFFER, fbo);
      gl.framebufferTexture2D(gl.FRAMEBUFFER, gl.COLOR_ATTACHMENT0, gl.TEXTURE_2D, target, 0);
      this.outputs.push({ texture: target, fbo });
    });
    // The estimated shading at the photo's size, once: infer's shading pasted over 1.
    this.old = floatTexture(gl, this.w, this.h, null);
    this.oldFbo = gl.createFramebuffer();
    gl.bindFramebuffer(gl.FRAMEBUFFER, this.oldFbo);
    gl.framebufferTexture2D(gl.FRAMEBUFFER, gl.COLOR_ATTACHMENT0, gl.TEXTURE_2D, this.old, 0);
    this.runPaste(this.olds, 1, 0, this.oldFbo);
  }

  runPaste(crops, base, out, fbo) {
    const gl = this.gl, program = this.paste;
    gl.bindFramebuffer(gl.FRAMEBUFFER, fbo);
    gl.viewport(0, 0, this.w, this.h);
    gl.useProgram(program);
    const u = (name) => gl.getUniformLocation(program, name);
    let unit = 0;
    const bind = (name, texture) => {
      gl.activeTexture(gl.TEXTURE0 + unit);
      gl.bindTexture(gl.TEXTURE_2D, texture);
      gl.uniform1i(u(name), unit++);
    };
    bind('u_photo', this.photo);
    // The estimated shading is not read while it is the pass's own target (the first pass).
    bind('u_old', fbo === this.oldFbo ? this.photo : this.old);
    bind('u_lines', this.lines);
    crops.forEach((texture, k) => bind('u_crop' + k, texture));
    gl.uniform4fv(u('u_t'), this.faces.flatMap((f) => f.photo_to_crop));
    gl.uniform1iv(u('u_crop_size'), this.faces.map((f) => f.crop_size));
    gl.uniform1iv(u('u_line_count'), this.faces.map((f) => f.mask_lines.length));
    gl.uniform1f(u('u_feather'), data.feather);
    gl.uniform1f(u('u_epsilon'), 0.02);
    gl.uniform1i(u('u_height'), this.h);
    gl.uniform1i(u('u_base'), base);
    gl.uniform1i(u('u_out'), out);
    gl.drawArrays(gl.TRIANGLES, 0, 3);
  }

  // Renders every face under `light` (27 coefficients, photo frame) and pastes them into the canvas.
  render(light, mode, visibility) {
    const gl = this.gl, render = mode === 'render' ? 1 : 0;
    gl.useProgram(this.crop);
    const u = (name) => gl.getUniformLocation(this.crop, name);
    this.faces.forEach((face, k) => {
      const s = face.crop_size, m = face.to_crop, cropLight = new Float32Array(27);
      for (let c = 0; c < 3; ++c)
        for (let r = 0; r < 9; ++r) {
          let sum = 0;
          for (let i = 0; i < 9; ++i) sum += m[r * 9 + i] * light[c * 9 + i];
          cropLight[c * 9 + r] = sum;
        }
      gl.bindFramebuffer(gl.FRAMEBUFFER, this.outputs[k].fbo);
      gl.viewport(0, 0, s, s);
      gl.activeTexture(gl.TEXTURE0);
      gl.bindTexture(gl.TEXTURE_2D, this.inputs[k]);
      gl.uniform1i(u('u_in'), 0);
      gl.uniform1i(u('u_size'), s);
      gl.uniform1fv(u('u_light[0]'), cropLight);
      gl.uniform1i(u('u_render'), render);
      gl.uniform1i(u('u_visibility'), visibility ? 1 : 0);
      gl.drawArrays(gl.TRIANGLES, 0, 3);
    });
    // Outside the faces' regions both modes give the photo: drawn once, then only the regions.
    if (this.drawn) {
      gl.enable(gl.SCISSOR_TEST);
      for (const [x, y, w, h] of this.faces.map((f) => f.region)) {
        gl.scissor(x, this.h - y - h, w, h);
        this.runPaste(this.outputs.map((o) => o.texture), render ? 0 : 1, render ? 1 : 2, null);
      }
      gl.disable(gl.SCISSOR_TEST);
    } else {
      this.runPaste(this.outputs.map((o) => o.texture), render ? 0 : 1, render ? 1 : 2, null);
      this.drawn = true;
    }
  }

  // The canvas's RGBA bytes, top row first.
  pixels() {
    const gl = this.gl, out = new Uint8Array(this.w * this.h * 4), flipped = new Uint8Array(out.length);
    gl.bindFramebuffer(gl.FRAMEBUFFER, null);
    gl.readPixels(0, 0, this.w, this.h, gl.RGBA, gl.UNSIGNED_BYTE, out);
    const row = this.w * 4;
    for (let y = 0; y < this.h; ++y) flipped.set(out.subarray((this.h - 1 - y) * row, (this.h - y) * row), y * row);
    return flipped;
  }
}

// ---- Small spheres: a light's shading, a pixel's visibility ----
function drawSphere(canvas, value) {
  const ctx = canvas.getContext('2d'), n = canvas.width, image = ctx.createImageData(n, n), values = [];
  let top = 1e-9;
  for (let py = 0; py < n; ++py)
    for (let px = 0; px < n; ++px) {
      const x = (px + 0.5) / n * 2 - 1, y = 1 - (py + 0.5) / n * 2, r2 = x * x + y * y;
      const rgb = r2 > 1 ? null : value(x, y, Math.sqrt(1 - r2));
      values.push(rgb);
      if (rgb) top = Math.max(top, ...rgb);
    }
  values.forEach((rgb, i) => {
    if (!rgb) return;
    for (let c = 0; c < 3; ++c) image.data[4 * i + c] = Math.round(255 * linearToSrgb(rgb[c] / top));
    image.data[4 * i + 3] = 255;
  });
  ctx.putImageData(image, 0, 0);
}

// The light's shading of a white unoccluded sphere, 1/pi sum A_l L_i Y_i(n) (light_preview.h).
function drawLightSphere(canvas, light) {
  drawSphere(canvas, (x, y, z) => {
    const b = shBasis(x, y, z), rgb = [0, 0, 0];
    for (let c = 0; c < 3; ++c) for (let i = 0; i < 9; ++i) rgb[c] += BAND_FACTOR[i] * light[c * 9 + i] * b[i] / Math.PI;
    return rgb;
  });
}

function lightFileText(light) {
  const channel = (c) => light.slice(c * 9, c * 9 + 9);
  return JSON.stringify({
    format: 'facetool-light', version: 1,
    basis: 'real SH, degree <= 2, index l(l+1)+m, orthonormal, no Condon-Shortley phase',
    frame: 'right-handed, +Y up, camera at +Z looking down -Z',
    coefficients: { r: channel(0), g: channel(1), b: channel(2) },
    metadata: { created_by: 'facetool view', photo: data.name },
  }, null, 2) + '\n';
}

function parseLightFile(text) {
  const json = JSON.parse(text);
  const k = json.coefficients;
  if (!k || ![k.r, k.g, k.b].every((a) => Array.isArray(a) && a.length === 9 && a.every(Number.isFinite)))
    throw new Error('not a facetool light file (coefficients r, g, b of 9 numbers each)');
  return [...k.r, ...k.g, ...k.b];
}

function download(name, blob) {
  const a = document.createElement('a');
  a.href = URL.createObjectURL(blob);
  a.download = name;
  a.click();
  setTimeout(() => URL.revokeObjectURL(a.href), 1000);
}

// ---- The page ----
async function main() {
  const started = performance.now();
  const view = $('view'), relitCanvas = $('relit');
  view.width = data.width;
  view.height = data.height;
  const images = { photo: await loadImage(data.photo), mask: await loadImage(data.mask) };
  for (const layer of data.layers) images[layer.name] = await loadImage(layer.url);
  const planes = data.faces.map(unpackFace);
  let relighter = null;
  try {
    relighter = new Relighter(relitCanvas, images.photo, data.faces, planes);
  } catch (e) {
    $('status').textContent = e.message;
  }
  const names = ['photo', ...data.layers.map((l) => l.name), 'mask'].concat(relighter ? ['relit'] : []);
  for (const select of [$('left-layer'), $('right-layer')])
    for (const name of names) select.add(new Option(name, name));
  $('left-layer').value = 'photo';
  $('right-layer').value = relighter ? 'relit' : 'albedo';
  data.presets.forEach((p, i) => $('preset').add(new Option(p.name, String(i))));

  const state = { light: null, mode: 'ratio', visibility: true, loadedLight: null };
  const colour = () => {
    const hex = $('colour').value;
    return [1, 3, 5].map((i) => srgbToLinear(parseInt(hex.slice(i, i + 2), 16) / 255));
  };
  function currentLight() {
    if (state.loadedLight) return state.loadedLight.map((v) => v * Number($('intensity').value));
    const preset = $('preset').value;
    if (preset !== '') return data.presets[Number(preset)].light.map((v) => v * Number($('intensity').value));
    return directionalLight(Number($('azimuth').value), Number($('elevation').value), Number($('ambient').value),
      Number($('intensity').value), colour());
  }

  function drawView() {
    const ctx = view.getContext('2d'), split = Math.round(Number($('wipe').value) * data.width);
    const source = (name) => (name === 'relit' ? relitCanvas : images[name]);
    ctx.clearRect(0, 0, data.width, data.height);
    if (split > 0) ctx.drawImage(source($('left-layer').value), 0, 0, split, data.height, 0, 0, split, data.height);
    if (split < data.width)
      ctx.drawImage(source($('right-layer').value), split, 0, data.width - split, data.height, split, 0,
        data.width - split, data.height);
    if ($('show-landmarks').checked) {
      ctx.strokeStyle = '#0f0';
      ctx.fillStyle = '#ff0';
      const r = Math.max(1, data.width / 300);
      for (const face of data.faces) {
        const [x0, y0, x1, y1] = face.box;
        ctx.strokeRect(x0, y0, x1 - x0, y1 - y0);
        for (const [x, y] of face.landmarks) ctx.fillRect(x - r, y - r, 2 * r, 2 * r);
      }
    }
    if (split > 0 && split < data.width) {
      ctx.fillStyle = '#fff';
      ctx.fillRect(split - 1, 0, 1, data.height);
    }
  }

  function update() {
    state.light = currentLight();
    state.mode = $('mode').value;
    state.visibility = $('visibility').checked;
    if (relighter) relighter.render(state.light, state.mode, state.visibility);
    drawLightSphere($('light-sphere'), state.light);
    drawView();
  }

  // The light's direction from a drag on its sphere (the front hemisphere; the rim is sideways).
  function dragLight(event) {
    const box = $('light-sphere').getBoundingClientRect();
    let x = ((event.clientX - box.left) / box.width) * 2 - 1, y = 1 - ((event.clientY - box.top) / box.height) * 2;
    const r = Math.hypot(x, y);
    if (r > 1) { x /= r; y /= r; }
    const z = Math.sqrt(Math.max(0, 1 - x * x - y * y));
    $('azimuth').value = (Math.atan2(x, z) * 180 / Math.PI).toFixed(1);
    $('elevation').value = (Math.asin(Math.max(-1, Math.min(1, y))) * 180 / Math.PI).toFixed(1);
    $('preset').value = '';
    state.loadedLight = null;
    update();
  }
  $('light-sphere').addEventListener('pointerdown', (e) => {
    $('light-sphere').setPointerCapture(e.pointerId);
    dragLight(e);
  });
  $('light-sphere').addEventListener('pointermove', (e) => { if (e.buttons) dragLight(e); });
  for (const id of ['azimuth', 'elevation', 'ambient', 'colour'])
    $(id).addEventListener('input', () => { $('preset').value = ''; state.loadedLight = null; update(); });
  for (const id of ['intensity', 'visibility', 'mode'])
    $(id).addEventListener('input', update);
  $('preset').addEventListener('input', () => { state.loadedLight = null; update(); });
  for (const id of ['left-layer', 'right-layer', 'wipe', 'show-landmarks']) $(id).addEventListener('input', drawView);
  $('light-file').addEventListener('change', async () => {
    const file = $('light-file').files[0];
    if (!file) return;
    try {
      state.loadedLight = parseLightFile(await file.text());
      $('status').textContent = 'light: ' + file.name;
      update();
    } catch (e) {
      $('status').textContent = file.name + ': ' + e.message;
    }
  });
  $('save-png').addEventListener('click', () => relitCanvas.toBlob((blob) => download(data.name + '_relit.png', blob), 'image/png'));
  $('save-light').addEventListener('click', () => download(data.name + '_light.json', new Blob([lightFileText(state.light)], { type: 'application/json' })));

  // Each face: its estimated light as a sphere and as numbers.
  data.faces.forEach((face, k) => {
    const div = document.createElement('div'), title = document.createElement('div'), sphere = document.createElement('canvas');
    div.className = 'face';
    title.textContent = `face ${k} (${face.folder})`;
    sphere.width = sphere.height = 96;
    drawLightSphere(sphere, face.light);
    const numbers = document.createElement('pre');
    numbers.textContent = ['R', 'G', 'B'].map((c, i) => c + ' ' + face.light.slice(i * 9, i * 9 + 9).map((v) => v.toFixed(3)).join(' ')).join('\n');
    div.append(title, sphere, numbers);
    $('faces').append(div);
  });

  // Hover: the pixel's normal, albedo and visibility from its face's crop (nearest sample).
  view.addEventListener('mousemove', (event) => {
    const box = view.getBoundingClientRect();
    const x = Math.floor((event.clientX - box.left) / box.width * data.width);
    const y = Math.floor((event.clientY - box.top) / box.height * data.height);
    for (let k = data.faces.length - 1; k >= 0; --k) {
      const face = data.faces[k], at = cropPosition(face, x, y), s = face.crop_size;
      if (at.alpha <= 0) continue;
      const i = Math.min(s - 1, Math.max(0, Math.round(at.cy))) * s + Math.min(s - 1, Math.max(0, Math.round(at.cx)));
      const p = planes[k], f = (c) => p[c][i].toFixed(3);
      const v = [3, 4, 5, 6, 7, 8, 9, 10, 11].map((c) => p[c][i]);
      $('hover').textContent = `pixel ${x}, ${y} (face ${k}, crop frame)\nnormal     ${f(0)} ${f(1)} ${f(2)}\n` +
        `albedo     ${f(12)} ${f(13)} ${f(14)}\nvisibility ${v.map((a) => a.toFixed(2)).join(' ')}`;
      drawSphere($('hover-sphere'), (sx, sy, sz) => {
        const b = shBasis(sx, sy, sz);
        let sum = 0;
        for (let j = 0; j < 9; ++j) sum += v[j] * b[j];
        const g = Math.max(0, sum);
        return [g, g, g];
      });
      return;
    }
    $('hover').textContent = `pixel ${x}, ${y}: no face`;
  });

  update();
  const openMs = performance.now() - started;
  $('status').textContent = (relighter ? '' : $('status').textContent + ' ') +
    `${data.width}x${data.height}, ${data.faces.length} face(s), mask ${data.mask_shape}`;

  // For tests and scripts (docs/viewer.md): the page driven without a mouse.
  window.facetoolView = {
    openMs,
    errors,
    setDirectional(azimuth, elevation, ambient, intensity) {
      $('azimuth').value = azimuth; $('elevation').value = elevation; $('ambient').value = ambient;
      $('intensity').value = intensity; $('preset').value = ''; $('colour').value = '#ffffff'; state.loadedLight = null;
      update();
    },
    setLight(light) { state.loadedLight = light.slice(); $('intensity').value = 1; update(); },
    setMode(mode, visibility) { $('mode').value = mode; $('visibility').checked = visibility; update(); },
    setWipe(left, right, position) { $('left-layer').value = left; $('right-layer').value = right; $('wipe').value = position; drawView(); },
    light: () => state.light.slice(),
    lightFileText: () => lightFileText(state.light),
    relitPixels: () => relighter.pixels(),
    viewPixels: () => view.getContext('2d').getImageData(0, 0, data.width, data.height).data,
    // Frames of a light turning about the head, each finished (one pixel read back), in ms.
    frameTimes(frames) {
      const times = [];
      for (let f = 0; f < frames; ++f) {
        const t0 = performance.now();
        $('azimuth').value = (f * 360 / frames) - 180;
        update();
        relighter.gl.readPixels(0, 0, 1, 1, relighter.gl.RGBA, relighter.gl.UNSIGNED_BYTE, new Uint8Array(4));
        times.push(performance.now() - t0);
      }
      return times;
    },
  };
  document.body.dataset.ready = '1';
}

main().catch((e) => {
  errors.push(String(e && e.message));
  $('status').textContent = 'error: ' + (e && e.message);
  document.body.dataset.ready = 'error';
});
})();
