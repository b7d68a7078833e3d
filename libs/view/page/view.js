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
// 8-bit sRGB of linear values in [0, 1] at 1/4096 steps: for the small spheres, drawn often.
const SRGB8 = Uint8Array.from({ length: 4097 }, (_, i) => Math.round(255 * linearToSrgb(i / 4096)));

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

// The per-pixel work that does not depend on the light, done once at the size of the faces'
// union box U (rows bottom up, as the framebuffer's): the photo decoded to linear RGB, and each
// face's paste-back weight from its mask's edges (paste_back.cpp), four faces per texture.
function prepareShader(faceCount, maxLines) {
  return `#version 300 es
precision highp float; precision highp int; precision highp sampler2D;
uniform sampler2D u_photo; uniform sampler2D u_lines;
uniform vec4 u_t[${faceCount}]; uniform int u_line_count[${faceCount}];
uniform float u_feather; uniform ivec4 u_union; uniform int u_first; uniform int u_out;
out vec4 o;
float toLinear(float v) { return v <= 0.04045 ? v / 12.92 : pow((v + 0.055) / 1.055, 2.4); }
float weight(int k, vec2 p) {
  vec4 t = u_t[k];
  vec2 c = vec2(t.x * p.x - t.y * p.y + t.z, t.y * p.x + t.x * p.y + t.w);
  float depth = 1e30;
  for (int e = 0; e < ${maxLines}; ++e) {
    if (e >= u_line_count[k]) break;
    vec3 l = texelFetch(u_lines, ivec2(e, k), 0).xyz;
    float side = l.x * c.x + l.y * c.y + l.z;
    if (side <= 0.0) return 0.0;
    depth = min(depth, side);
  }
  return u_feather > 0.0 ? clamp(depth / u_feather, 0.0, 1.0) : 1.0;
}
void main() {
  ivec2 q = ivec2(gl_FragCoord.xy);
  ivec2 pi = ivec2(u_union.x + q.x, u_union.y + u_union.w - 1 - q.y);
  if (u_out == 0) {
    vec3 s = texelFetch(u_photo, pi, 0).rgb;
    o = vec4(toLinear(s.r), toLinear(s.g), toLinear(s.b), 1.0);
    return;
  }
  vec4 w = vec4(0.0);
  for (int i = 0; i < 4; ++i) if (u_first + i < ${faceCount}) w[i] = weight(u_first + i, vec2(pi));
  o = w;
}`;
}

// relight's paste-back of every face, in order, at one pixel of U (bilinear in the crop, blended
// with the prepared weight), then the mode's last step. One program per use, without the code the
// use does not need (in SwiftShader, the software WebGL, code a branch skips still costs):
// OUT 0 the pasted value as it is (the estimated shading, pasted over 1); 1 render: pasted over the
// photo, sRGB-encoded; 2 ratio: pasted over 1, times the prepared photo / (old shading + epsilon),
// sRGB-encoded. Pixels of no face: KEEP 1 left as the target holds them, 0 the photo's bytes.
// u_origin: where U's first row and column are in gl_FragCoord.
function pasteShader(faceCount, out, keep) {
  let samplers = '', calls = '';
  for (let k = 0; k < faceCount; ++k) {
    samplers += `uniform sampler2D u_crop${k};\n`;
    calls += `  acc = pasteFace(u_crop${k}, ${k}, w${k >> 2}[${k & 3}], p, acc);\n`;
  }
  let weights = '';
  for (let g = 0; g < Math.ceil(faceCount / 4); ++g)
    weights += `  vec4 w${g} = texelFetch(u_weights${g}, q, 0);\n`;
  const weightSamplers = Array.from({ length: Math.ceil(faceCount / 4) }, (_, g) => `uniform sampler2D u_weights${g};`).join(' ');
  return `#version 300 es
#define OUT ${out}
#define KEEP ${keep}
precision highp float; precision highp int; precision highp sampler2D;
${samplers}${weightSamplers}
uniform sampler2D u_linear; uniform sampler2D u_ratio; uniform sampler2D u_photo; uniform sampler2D u_srgb;
uniform vec4 u_t[${faceCount}]; uniform int u_crop_size[${faceCount}];
uniform float u_epsilon; uniform ivec4 u_union; uniform ivec2 u_origin;
out vec4 o;
// round(255 x sRGB(v)) / 255 from u_srgb (srgbSteps()): at v's 1/4096 step, the level at the
// step's start and the value where the next level starts.
float toSrgb8(float v) {
  float x = clamp(v, 0.0, 1.0);
  int i = min(int(x * 4096.0), 4095);
  vec2 s = texelFetch(u_srgb, ivec2(i & 63, i >> 6), 0).xy;
  return (s.x + (x >= s.y ? 1.0 : 0.0)) / 255.0;
}
vec3 pasteFace(sampler2D crop, int k, float a, vec2 p, vec3 acc) {
  if (a <= 0.0) return acc;
  vec4 t = u_t[k];
  vec2 c = vec2(t.x * p.x - t.y * p.y + t.z, t.y * p.x + t.x * p.y + t.w);
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
  ivec2 q = ivec2(gl_FragCoord.xy) - u_origin;
  vec2 p = vec2(float(u_union.x + q.x), float(u_union.y + u_union.w - 1 - q.y));
${weights}#if OUT != 0
  // No face here: both modes give the photo.
  if (${Array.from({ length: Math.ceil(faceCount / 4) }, (_, g) => `dot(w${g}, vec4(1.0)) <= 0.0`).join(' && ')}) {
#if KEEP
    discard;
#else
    o = vec4(texelFetch(u_photo, ivec2(p), 0).rgb, 1.0);
    return;
#endif
  }
#endif
#if OUT == 1
  vec3 acc = texelFetch(u_linear, q, 0).rgb;
#else
  vec3 acc = vec3(1.0);
#endif
${calls}#if OUT == 0
  o = vec4(acc, 1.0);
#else
#if OUT == 2
  acc = texelFetch(u_ratio, q, 0).rgb * (max(acc, 0.0) + u_epsilon);
#endif
  o = vec4(toSrgb8(acc.r), toSrgb8(acc.g), toSrgb8(acc.b), 1.0);
#endif
}`;
}

// The ratio mode's per-pixel factor that does not depend on the light, over U: photo / (the
// estimated shading + epsilon), both linear (relight's guarded ratio: photo x (new + e) / (old + e)).
const RATIO = `#version 300 es
precision highp float; precision highp sampler2D;
uniform sampler2D u_linear; uniform sampler2D u_old; uniform float u_epsilon; out vec4 o;
void main() {
  ivec2 q = ivec2(gl_FragCoord.xy);
  o = vec4(texelFetch(u_linear, q, 0).rgb / (max(texelFetch(u_old, q, 0).rgb, 0.0) + u_epsilon), 1.0);
}`;
const RATIO_EPSILON = 0.02;

// The table toSrgb8 reads, 4096 steps of linear values as 64 x 64 texels: per step the 8-bit level
// round(255 sRGB(v)) at its start and the value where the next level starts (2: none in the step).
// A step holds at most one start: the curve rises at most 255 x 12.92 / 4096 = 0.8 levels per step.
function srgbSteps() {
  const steps = 4096, table = new Float32Array(steps * 4);
  const starts = Array.from({ length: 255 }, (_, k) => srgbToLinear((k + 0.5) / 255));
  let level = 0;
  for (let i = 0; i < steps; ++i) {
    while (level < 255 && starts[level] <= i / steps) ++level;
    table[4 * i] = level;
    table[4 * i + 1] = level < 255 && starts[level] < (i + 1) / steps ? starts[level] : 2;
  }
  return table;
}

// The photo's sRGB bytes as they are, for the canvas outside the faces (drawn once).
const COPY = `#version 300 es
precision highp float; precision highp sampler2D;
uniform sampler2D u_photo; uniform int u_height; out vec4 o;
void main() { o = vec4(texelFetch(u_photo, ivec2(int(gl_FragCoord.x), u_height - 1 - int(gl_FragCoord.y)), 0).rgb, 1.0); }`;

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

function targetTexture(gl, width, height) {
  const texture = floatTexture(gl, width, height, null), fbo = gl.createFramebuffer();
  gl.bindFramebuffer(gl.FRAMEBUFFER, fbo);
  gl.framebufferTexture2D(gl.FRAMEBUFFER, gl.COLOR_ATTACHMENT0, gl.TEXTURE_2D, texture, 0);
  return { texture, fbo };
}

// The relit faces in a WebGL2 canvas the size of U, the box around the faces' regions, shown over
// the photo's <img> as it is. A frame: per face the crop pass, then the paste pass over the faces'
// regions only; the rest of the canvas stays transparent (the photo shows through). The drawing
// buffer is not preserved (the browser swaps it instead of copying it each frame): what is read
// back (pixels(), the saved PNG) is rendered again at the photo's size into a texture of its own.
class Relighter {
  constructor(canvas, photoImage, faces, planes) {
    const gl = canvas.getContext('webgl2', { preserveDrawingBuffer: false, antialias: false, depth: false, stencil: false });
    if (!gl) throw new Error('this browser has no WebGL2; the layers are shown, the relighting is not');
    if (!gl.getExtension('EXT_color_buffer_float')) throw new Error('this browser cannot render to float textures (EXT_color_buffer_float)');
    this.gl = gl;
    this.w = data.width;
    this.h = data.height;
    this.faces = faces;
    this.uniforms = new Map();
    const buffer = gl.createBuffer();
    gl.bindBuffer(gl.ARRAY_BUFFER, buffer);
    gl.bufferData(gl.ARRAY_BUFFER, new Float32Array([-1, -1, 3, -1, -1, 3]), gl.STATIC_DRAW);
    gl.enableVertexAttribArray(0);
    gl.vertexAttribPointer(0, 2, gl.FLOAT, false, 0, 0);
    const maxLines = Math.max(...faces.map((f) => f.mask_lines.length));
    this.crop = compile(gl, VERTEX, cropShader(data.triple));
    this.pastePrograms = new Map();
    const prepare = compile(gl, VERTEX, prepareShader(faces.length, maxLines)), copy = compile(gl, VERTEX, COPY);

    // U, the box around every face's region (photo pixels, top-down rows).
    const x0 = Math.min(...faces.map((f) => f.region[0])), y0 = Math.min(...faces.map((f) => f.region[1]));
    const x1 = Math.max(...faces.map((f) => f.region[0] + f.region[2]));
    const y1 = Math.max(...faces.map((f) => f.region[1] + f.region[3]));
    this.union = [x0, y0, Math.max(1, x1 - x0), Math.max(1, y1 - y0)];
    const [uw, uh] = [this.union[2], this.union[3]];
    canvas.width = uw;
    canvas.height = uh;

    gl.pixelStorei(gl.UNPACK_COLORSPACE_CONVERSION_WEBGL, gl.NONE);
    gl.pixelStorei(gl.UNPACK_PREMULTIPLY_ALPHA_WEBGL, false);
    const photo = (this.photo = gl.createTexture());
    gl.bindTexture(gl.TEXTURE_2D, photo);
    gl.texImage2D(gl.TEXTURE_2D, 0, gl.RGBA8, gl.RGBA, gl.UNSIGNED_BYTE, photoImage);
    for (const p of [gl.TEXTURE_MIN_FILTER, gl.TEXTURE_MAG_FILTER]) gl.texParameteri(gl.TEXTURE_2D, p, gl.NEAREST);
    const lines = new Float32Array(maxLines * faces.length * 4);
    faces.forEach((f, k) => f.mask_lines.forEach((l, e) => lines.set([l[0], l[1], l[2], 1], 4 * (k * maxLines + e))));
    const lineTexture = floatTexture(gl, maxLines, faces.length, lines);
    this.srgb = floatTexture(gl, 64, 64, srgbSteps());

    // Once: the photo in linear RGB and the faces' weights over U, then the estimated shading
    // (infer's, pasted over 1) and from it the ratio mode's factor (RATIO).
    this.linear = targetTexture(gl, uw, uh);
    this.weights = [];
    for (let first = 0; first < faces.length; first += 4) this.weights.push(targetTexture(gl, uw, uh));
    gl.useProgram(prepare);
    // (Textures are bound after every texture is made: making one binds it to the active unit.)
    this.bind(prepare, [['u_photo', photo], ['u_lines', lineTexture]]);
    const u = (name) => this.uniform(prepare, name);
    gl.uniform4fv(u('u_t'), faces.flatMap((f) => f.photo_to_crop));
    gl.uniform1iv(u('u_line_count'), faces.map((f) => f.mask_lines.length));
    gl.uniform1f(u('u_feather'), data.feather);
    gl.uniform4iv(u('u_union'), this.union);
    gl.viewport(0, 0, uw, uh);
    gl.bindFramebuffer(gl.FRAMEBUFFER, this.linear.fbo);
    gl.uniform1i(u('u_out'), 0);
    gl.drawArrays(gl.TRIANGLES, 0, 3);
    this.weights.forEach((target, g) => {
      gl.bindFramebuffer(gl.FRAMEBUFFER, target.fbo);
      gl.uniform1i(u('u_first'), 4 * g);
      gl.uniform1i(u('u_out'), 1);
      gl.drawArrays(gl.TRIANGLES, 0, 3);
    });

    this.inputs = [];
    this.outputs = [];
    const olds = [];
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
      olds.push(floatTexture(gl, s, s, old));
      this.outputs.push(targetTexture(gl, s, s));
    });
    const old = targetTexture(gl, uw, uh);
    this.runPaste(olds, 0, old.fbo, [0, 0], null, 0);
    this.ratio = targetTexture(gl, uw, uh);
    const ratio = compile(gl, VERTEX, RATIO);
    gl.useProgram(ratio);
    this.bind(ratio, [['u_linear', this.linear.texture], ['u_old', old.texture]]);
    gl.uniform1f(this.uniform(ratio, 'u_epsilon'), RATIO_EPSILON);
    gl.drawArrays(gl.TRIANGLES, 0, 3);

    // What is read back: the whole photo in 8 bits, its sRGB bytes everywhere, once; U is
    // pasted over it again for each read.
    this.full = { texture: gl.createTexture(), fbo: gl.createFramebuffer() };
    gl.bindTexture(gl.TEXTURE_2D, this.full.texture);
    gl.texStorage2D(gl.TEXTURE_2D, 1, gl.RGBA8, this.w, this.h);
    gl.bindFramebuffer(gl.FRAMEBUFFER, this.full.fbo);
    gl.framebufferTexture2D(gl.FRAMEBUFFER, gl.COLOR_ATTACHMENT0, gl.TEXTURE_2D, this.full.texture, 0);
    gl.viewport(0, 0, this.w, this.h);
    gl.useProgram(copy);
    this.bind(copy, [['u_photo', photo]]);
    gl.uniform1i(this.uniform(copy, 'u_height'), this.h);
    gl.drawArrays(gl.TRIANGLES, 0, 3);
    this.lastOut = 2;
  }

  uniform(program, name) {
    let perProgram = this.uniforms.get(program);
    if (!perProgram) this.uniforms.set(program, (perProgram = new Map()));
    if (!perProgram.has(name)) perProgram.set(name, this.gl.getUniformLocation(program, name));
    return perProgram.get(name);
  }

  bind(program, textures) {
    const gl = this.gl;
    textures.forEach(([name, texture], unit) => {
      gl.activeTexture(gl.TEXTURE0 + unit);
      gl.bindTexture(gl.TEXTURE_2D, texture);
      gl.uniform1i(this.uniform(program, name), unit);
    });
  }

  // The paste pass into `fbo` (null: the canvas), U's first pixel at `origin` of the target;
  // `scissors`: the boxes of the target drawn (null: all of U); `keep` 1: pixels of no face are
  // left as they are, 0: they get the photo's bytes.
  runPaste(crops, out, fbo, origin, scissors, keep) {
    const gl = this.gl, key = `${out} ${keep}`;
    if (!this.pastePrograms.has(key)) this.pastePrograms.set(key, compile(gl, VERTEX, pasteShader(this.faces.length, out, keep)));
    const program = this.pastePrograms.get(key), u = (name) => this.uniform(program, name);
    gl.bindFramebuffer(gl.FRAMEBUFFER, fbo);
    gl.viewport(origin[0], origin[1], this.union[2], this.union[3]);
    gl.useProgram(program);
    const textures = [['u_linear', this.linear.texture], ['u_photo', this.photo], ['u_srgb', this.srgb]];
    if (this.ratio) textures.push(['u_ratio', this.ratio.texture]);
    this.weights.forEach((target, g) => textures.push(['u_weights' + g, target.texture]));
    crops.forEach((texture, k) => textures.push(['u_crop' + k, texture]));
    this.bind(program, textures);
    gl.uniform4fv(u('u_t'), this.faces.flatMap((f) => f.photo_to_crop));
    gl.uniform1iv(u('u_crop_size'), this.faces.map((f) => f.crop_size));
    gl.uniform1f(u('u_epsilon'), RATIO_EPSILON);
    gl.uniform4iv(u('u_union'), this.union);
    gl.uniform2iv(u('u_origin'), origin);
    if (!scissors) {
      gl.drawArrays(gl.TRIANGLES, 0, 3);
      return;
    }
    gl.enable(gl.SCISSOR_TEST);
    for (const [x, y, w, h] of scissors) {
      gl.scissor(x, y, w, h);
      gl.drawArrays(gl.TRIANGLES, 0, 3);
    }
    gl.disable(gl.SCISSOR_TEST);
  }

  // Renders every face under `light` (27 coefficients, photo frame) and pastes them into the canvas.
  render(light, mode, visibility) {
    const gl = this.gl, render = mode === 'render' ? 1 : 0, program = this.crop;
    const u = (name) => this.uniform(program, name);
    gl.useProgram(program);
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
      this.bind(program, [['u_in', this.inputs[k]]]);
      gl.uniform1i(u('u_size'), s);
      gl.uniform1fv(u('u_light[0]'), cropLight);
      gl.uniform1i(u('u_render'), render);
      gl.uniform1i(u('u_visibility'), visibility ? 1 : 0);
      gl.drawArrays(gl.TRIANGLES, 0, 3);
    });
    // Outside the faces' regions both modes give the photo, shown under the canvas: only the
    // regions are drawn (U's rows bottom up: a region's first row is its bottom one).
    const [ux, uy, , uh] = this.union;
    const scissors = this.faces.map((f) => [f.region[0] - ux, uy + uh - f.region[1] - f.region[3], f.region[2], f.region[3]]);
    this.lastOut = render ? 1 : 2;
    this.runPaste(this.outputs.map((o) => o.texture), this.lastOut, null, [0, 0], scissors, 1);
  }

  // The relit photo's RGBA bytes, top row first, as the page shows it (the last render()'s).
  pixels() {
    const gl = this.gl, out = new Uint8Array(this.w * this.h * 4), flipped = new Uint8Array(out.length);
    const origin = [this.union[0], this.h - this.union[1] - this.union[3]];
    this.runPaste(this.outputs.map((o) => o.texture), this.lastOut, this.full.fbo, origin, null, 0);
    gl.readPixels(0, 0, this.w, this.h, gl.RGBA, gl.UNSIGNED_BYTE, out);
    const row = this.w * 4;
    for (let y = 0; y < this.h; ++y) flipped.set(out.subarray((this.h - 1 - y) * row, (this.h - y) * row), y * row);
    return flipped;
  }
}

// ---- Small spheres: a light's shading, a pixel's visibility ----
// Per sphere size: each pixel inside the disc and its 9 SH basis values at the sphere's normal.
const sphereGrids = new Map();
function sphereGrid(n) {
  if (sphereGrids.has(n)) return sphereGrids.get(n);
  const inside = [], basis = [];
  for (let py = 0; py < n; ++py)
    for (let px = 0; px < n; ++px) {
      const x = (px + 0.5) / n * 2 - 1, y = 1 - (py + 0.5) / n * 2, r2 = x * x + y * y;
      if (r2 > 1) continue;
      inside.push(py * n + px);
      basis.push(...shBasis(x, y, Math.sqrt(1 - r2)));
    }
  const grid = { inside: Int32Array.from(inside), basis: Float32Array.from(basis) };
  sphereGrids.set(n, grid);
  return grid;
}

// A sphere whose pixel at normal n has colour sum_i weights[c][i] Y_i(n) (clamped at 0), scaled
// so that its brightest channel is 1, sRGB-encoded.
// Each canvas keeps its image and its buffer of sums between draws (a drag draws one per frame).
const sphereImages = new Map();
function drawSphere(canvas, weights) {
  const n = canvas.width, { inside, basis } = sphereGrid(n), w = Float32Array.from(weights.flat());
  if (!sphereImages.has(canvas)) {
    const ctx = canvas.getContext('2d');
    sphereImages.set(canvas, { ctx, image: ctx.createImageData(n, n), rgb: new Float32Array(inside.length * 3) });
  }
  const { ctx, image, rgb } = sphereImages.get(canvas);
  let top = 1e-9;
  for (let p = 0; p < inside.length; ++p)
    for (let c = 0; c < 3; ++c) {
      let sum = 0;
      for (let i = 0; i < 9; ++i) sum += w[c * 9 + i] * basis[p * 9 + i];
      rgb[p * 3 + c] = sum;
      if (sum > top) top = sum;
    }
  const scale = 4096 / top;
  for (let p = 0; p < inside.length; ++p) {
    const at = 4 * inside[p];
    for (let c = 0; c < 3; ++c) image.data[at + c] = SRGB8[Math.min(4096, Math.max(0, Math.round(rgb[p * 3 + c] * scale)))];
    image.data[at + 3] = 255;
  }
  ctx.putImageData(image, 0, 0);
}

// The light's shading of a white unoccluded sphere, 1/pi sum A_l L_i Y_i(n) (light_preview.h).
function drawLightSphere(canvas, light) {
  drawSphere(canvas, [0, 1, 2].map((c) => BAND_FACTOR.map((a, i) => a * light[c * 9 + i] / Math.PI)));
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
function setText(field, value) {
  if (field.value !== value) field.value = value;
}

async function main() {
  const started = performance.now();
  const box = $('view-box'), overlay = $('overlay'), relitCanvas = document.createElement('canvas');
  box.style.aspectRatio = `${data.width} / ${data.height}`;
  box.style.maxWidth = `calc(80vh * ${data.width / data.height})`;
  overlay.width = data.width;
  overlay.height = data.height;
  // Only the photo is decoded before the page is ready (the relighting needs its pixels); the
  // layers are <img> elements the browser decodes when they are first shown.
  const urls = { photo: data.photo, mask: data.mask };
  for (const layer of data.layers) urls[layer.name] = layer.url;
  const photoImage = await loadImage(data.photo);
  const planes = data.faces.map(unpackFace);
  let relighter = null;
  try {
    relighter = new Relighter(relitCanvas, photoImage, data.faces, planes);
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

  // The wipe: two panes over each other, the right one clipped at the wipe (CSS, no copy of pixels).
  // The relit layer is the photo with the WebGL canvas over the faces' box; a layer on both sides
  // shows in the left pane only.
  const panes = [$('left-pane'), $('right-pane')], shown = ['', ''];
  let relitLayer = null;
  if (relighter) {
    relitLayer = document.createElement('div');
    relitLayer.className = 'relit';
    const [ux, uy, uw, uh] = relighter.union;
    Object.assign(relitCanvas.style, { left: `${100 * ux / data.width}%`, top: `${100 * uy / data.height}%`,
      width: `${100 * uw / data.width}%`, height: `${100 * uh / data.height}%` });
    relitLayer.append(layerElement('photo'), relitCanvas);
  }
  function layerElement(name) {
    if (name === 'relit') return relitLayer;
    const img = new Image();
    img.src = urls[name];
    img.alt = name;
    return img;
  }
  function drawView() {
    const left = $('left-layer').value, right = $('right-layer').value;
    const wanted = [left, right === left ? '' : right];
    wanted.forEach((name, i) => {
      if (shown[i] === name) return;
      panes[i].replaceChildren(...(name ? [layerElement(name)] : []));
      shown[i] = name;
      // A canvas put back in the page is drawn again (its buffer is not kept between frames).
      if (name === 'relit') requestUpdate();
    });
    const split = Math.round(Number($('wipe').value) * data.width), percent = `${(100 * split / data.width).toFixed(4)}%`;
    panes[1].style.clipPath = `inset(0 0 0 ${percent})`;
    $('wipe-line').style.left = percent;
    $('wipe-line').hidden = split <= 0 || split >= data.width;
    // The overlay is a layer the browser composites every frame: shown only when it holds something.
    overlay.hidden = !$('show-landmarks').checked;
    const ctx = overlay.getContext('2d');
    ctx.clearRect(0, 0, data.width, data.height);
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
  }

  function update() {
    state.light = currentLight();
    state.mode = $('mode').value;
    state.visibility = $('visibility').checked;
    if (relighter) relighter.render(state.light, state.mode, state.visibility);
    // The sphere only when its light changed (a mode or visibility switch leaves it as it is).
    if (String(state.light) !== drawnLight) drawLightSphere($('light-sphere'), state.light);
    drawnLight = String(state.light);
  }
  let drawnLight = '';
  // Input events only ask for a frame: at most one render per animation frame, however many
  // events arrive (a drag sends more than the display shows).
  let framePending = false;
  const frameStamps = [];
  function requestUpdate() {
    if (framePending) return;
    framePending = true;
    requestAnimationFrame((t) => {
      framePending = false;
      update();
      frameStamps.push(t);
    });
  }

  // The light's direction from a drag on its sphere (the front hemisphere; the rim is sideways).
  function dragLight(event) {
    const box = $('light-sphere').getBoundingClientRect();
    let x = ((event.clientX - box.left) / box.width) * 2 - 1, y = 1 - ((event.clientY - box.top) / box.height) * 2;
    const r = Math.hypot(x, y);
    if (r > 1) { x /= r; y /= r; }
    const z = Math.sqrt(Math.max(0, 1 - x * x - y * y));
    // Fields written only when their text changes: each write is a style and layout change.
    setText($('azimuth'), (Math.atan2(x, z) * 180 / Math.PI).toFixed(1));
    setText($('elevation'), (Math.asin(Math.max(-1, Math.min(1, y))) * 180 / Math.PI).toFixed(1));
    setText($('preset'), '');
    state.loadedLight = null;
    requestUpdate();
  }
  $('light-sphere').addEventListener('pointerdown', (e) => {
    try { $('light-sphere').setPointerCapture(e.pointerId); } catch (_) { /* a synthetic pointer */ }
    dragLight(e);
  });
  $('light-sphere').addEventListener('pointermove', (e) => { if (e.buttons) dragLight(e); });
  for (const id of ['azimuth', 'elevation', 'ambient', 'colour'])
    $(id).addEventListener('input', () => { $('preset').value = ''; state.loadedLight = null; requestUpdate(); });
  for (const id of ['intensity', 'visibility', 'mode'])
    $(id).addEventListener('input', requestUpdate);
  $('preset').addEventListener('input', () => { state.loadedLight = null; requestUpdate(); });
  for (const id of ['left-layer', 'right-layer', 'wipe', 'show-landmarks']) $(id).addEventListener('input', drawView);
  async function loadLightFile(file) {
    try {
      state.loadedLight = parseLightFile(await file.text());
      $('preset').value = '';
      $('status').textContent = 'light: ' + file.name;
      update();
    } catch (e) {
      $('status').textContent = file.name + ': ' + e.message;
    }
  }
  $('light-file').addEventListener('change', () => { if ($('light-file').files[0]) loadLightFile($('light-file').files[0]); });
  $('save-png').addEventListener('click', () => {
    if (!relighter) return;
    const canvas = document.createElement('canvas');
    canvas.width = data.width;
    canvas.height = data.height;
    canvas.getContext('2d').putImageData(new ImageData(new Uint8ClampedArray(relighter.pixels().buffer), data.width, data.height), 0, 0);
    canvas.toBlob((blob) => download(data.name + '_relit.png', blob), 'image/png');
  });
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
  function showPixel(x, y) {
    for (let k = data.faces.length - 1; k >= 0; --k) {
      const face = data.faces[k], at = cropPosition(face, x, y), s = face.crop_size;
      if (at.alpha <= 0) continue;
      const i = Math.min(s - 1, Math.max(0, Math.round(at.cy))) * s + Math.min(s - 1, Math.max(0, Math.round(at.cx)));
      const p = planes[k], f = (c) => p[c][i].toFixed(3);
      const v = [3, 4, 5, 6, 7, 8, 9, 10, 11].map((c) => p[c][i]);
      $('hover').textContent = `pixel ${x}, ${y} (face ${k}, crop frame)\nnormal     ${f(0)} ${f(1)} ${f(2)}\n` +
        `albedo     ${f(12)} ${f(13)} ${f(14)}\nvisibility ${v.map((a) => a.toFixed(3)).join(' ')}`;
      drawSphere($('hover-sphere'), [v, v, v]);
      return;
    }
    $('hover').textContent = `pixel ${x}, ${y}: no face`;
  }
  let hoverPending = null;
  box.addEventListener('mousemove', (event) => {
    const rect = box.getBoundingClientRect();
    const x = Math.min(data.width - 1, Math.floor((event.clientX - rect.left) / rect.width * data.width));
    const y = Math.min(data.height - 1, Math.floor((event.clientY - rect.top) / rect.height * data.height));
    if (hoverPending === null) requestAnimationFrame(() => { showPixel(...hoverPending); hoverPending = null; });
    hoverPending = [x, y];
  });

  update();
  drawView();
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
    // A drag as the browser delivers it: one pointer move on the light sphere per animation
    // frame for `frames` frames, each rendered in the page's own animation-frame callback.
    // Resolves to the frames shown per second over the drag.
    async dragFps(frames) {
      const sphere = $('light-sphere'), rect = sphere.getBoundingClientRect();
      const at = (f) => {
        const angle = 2 * Math.PI * f / frames;
        return { clientX: rect.left + rect.width * (0.5 + 0.35 * Math.cos(angle)),
                 clientY: rect.top + rect.height * (0.5 + 0.35 * Math.sin(angle)), buttons: 1, pointerId: 1, bubbles: true };
      };
      sphere.dispatchEvent(new PointerEvent('pointerdown', at(0)));
      await new Promise(requestAnimationFrame);
      frameStamps.length = 0;
      for (let f = 1; f <= frames; ++f) {
        sphere.dispatchEvent(new PointerEvent('pointermove', at(f)));
        await new Promise(requestAnimationFrame);
      }
      sphere.dispatchEvent(new PointerEvent('pointerup', at(frames)));
      const stamps = frameStamps.slice();
      return { frames: stamps.length, fps: 1000 * (stamps.length - 1) / (stamps[stamps.length - 1] - stamps[0]) };
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
