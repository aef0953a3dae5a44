// A small offline viewer for the binary glTF meshes tin_as_gltf writes:
// reads the .glb (JSON + BIN chunks), draws the one triangle mesh with
// WebGL 2 (vertex colours or the embedded PNG texture, one light), and
// turns it with the mouse (drag: rotate, wheel: zoom). Written for this
// page because browsers refuse to load module scripts and fetch() from
// file:// pages, which is how the demo page is opened; the meshes are
// handed over as base64 strings from a <script> file instead.
"use strict";

function parseGlb(buf) {
  const dv = new DataView(buf);
  if (dv.getUint32(0, true) !== 0x46546c67) throw new Error("not a binary glTF");
  const jsonLen = dv.getUint32(12, true);
  const json = JSON.parse(new TextDecoder().decode(new Uint8Array(buf, 20, jsonLen)));
  const binLen = dv.getUint32(20 + jsonLen, true);
  const bin = buf.slice(28 + jsonLen, 28 + jsonLen + binLen);
  const comps = { SCALAR: 1, VEC2: 2, VEC3: 3, VEC4: 4 };
  const accessor = (i) => {
    const a = json.accessors[i];
    const v = json.bufferViews[a.bufferView];
    const off = (v.byteOffset || 0) + (a.byteOffset || 0);
    const n = comps[a.type] * a.count;
    return a.componentType === 5126 ? new Float32Array(bin, off, n) : new Uint32Array(bin, off, n);
  };
  const prim = json.meshes[0].primitives[0];
  const at = prim.attributes;
  const mesh = {
    position: accessor(at.POSITION),
    normal: accessor(at.NORMAL),
    color: at.COLOR_0 !== undefined ? accessor(at.COLOR_0) : null,
    uv: at.TEXCOORD_0 !== undefined ? accessor(at.TEXCOORD_0) : null,
    indices: accessor(prim.indices),
    min: json.accessors[at.POSITION].min,
    max: json.accessors[at.POSITION].max,
    image: null,
    extras: json.nodes[0].extras || {},
  };
  if (json.images && json.images.length) {
    const v = json.bufferViews[json.images[0].bufferView];
    mesh.image = new Blob([new Uint8Array(bin, v.byteOffset || 0, v.byteLength)], { type: json.images[0].mimeType });
  }
  return mesh;
}

function base64ToBuffer(s) {
  const bytes = atob(s);
  const out = new Uint8Array(bytes.length);
  for (let i = 0; i < bytes.length; i++) out[i] = bytes.charCodeAt(i);
  return out.buffer;
}

const VS = `#version 300 es
in vec3 position; in vec3 normal; in vec3 color; in vec2 uv;
uniform mat4 mvp; out vec3 vNormal; out vec3 vColor; out vec2 vUv;
void main() { vNormal = normal; vColor = color; vUv = uv; gl_Position = mvp * vec4(position, 1.0); }`;
const FS = `#version 300 es
precision highp float;
in vec3 vNormal; in vec3 vColor; in vec2 vUv;
uniform bool textured; uniform sampler2D tex; out vec4 outColor;
void main() {
  vec3 base = vColor;
  if (textured) { vec4 t = texture(tex, vUv); if (t.a < 0.5) discard; base = pow(t.rgb, vec3(2.2)); }
  float light = 0.35 + 0.65 * max(dot(normalize(vNormal), normalize(vec3(-0.4, 1.0, 0.5))), 0.0);
  outColor = vec4(pow(base * light, vec3(1.0 / 2.2)), 1.0);
}`;

function mat4Mul(a, b) {
  const o = new Float32Array(16);
  for (let i = 0; i < 4; i++)
    for (let j = 0; j < 4; j++) {
      let s = 0;
      for (let k = 0; k < 4; k++) s += a[k * 4 + j] * b[i * 4 + k];
      o[i * 4 + j] = s;
    }
  return o;
}

function perspective(fovy, aspect, near, far) {
  const f = 1 / Math.tan(fovy / 2);
  const o = new Float32Array(16);
  o[0] = f / aspect; o[5] = f; o[10] = (far + near) / (near - far); o[11] = -1; o[14] = (2 * far * near) / (near - far);
  return o;
}

function view(yaw, pitch, dist) {
  // camera orbiting the origin: rotate the world by yaw (around y) and pitch
  // (around x), then move it dist away along -z
  const cy = Math.cos(yaw), sy = Math.sin(yaw), cp = Math.cos(pitch), sp = Math.sin(pitch);
  const ry = new Float32Array([cy, 0, -sy, 0, 0, 1, 0, 0, sy, 0, cy, 0, 0, 0, 0, 1]);
  const rx = new Float32Array([1, 0, 0, 0, 0, cp, sp, 0, 0, -sp, cp, 0, 0, 0, 0, 1]);
  const t = new Float32Array([1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, -dist, 1]);
  return mat4Mul(t, mat4Mul(rx, ry));
}

// Shows the mesh in `canvas`; resolves with the number of pixels drawn
// (different from the background) after the first frame.
async function showGlb(canvas, base64) {
  const mesh = parseGlb(base64ToBuffer(base64));
  const gl = canvas.getContext("webgl2", { preserveDrawingBuffer: true, antialias: true });
  if (!gl) throw new Error("WebGL 2 is not available");
  const sh = (type, src) => {
    const s = gl.createShader(type);
    gl.shaderSource(s, src);
    gl.compileShader(s);
    if (!gl.getShaderParameter(s, gl.COMPILE_STATUS)) throw new Error(gl.getShaderInfoLog(s));
    return s;
  };
  const prog = gl.createProgram();
  gl.attachShader(prog, sh(gl.VERTEX_SHADER, VS));
  gl.attachShader(prog, sh(gl.FRAGMENT_SHADER, FS));
  gl.linkProgram(prog);
  if (!gl.getProgramParameter(prog, gl.LINK_STATUS)) throw new Error(gl.getProgramInfoLog(prog));
  gl.useProgram(prog);
  const attrib = (name, data, size) => {
    const loc = gl.getAttribLocation(prog, name);
    if (loc < 0) return;
    if (!data) { gl.disableVertexAttribArray(loc); gl.vertexAttrib3f(loc, 0.8, 0.8, 0.8); return; }
    const b = gl.createBuffer();
    gl.bindBuffer(gl.ARRAY_BUFFER, b);
    gl.bufferData(gl.ARRAY_BUFFER, data, gl.STATIC_DRAW);
    gl.enableVertexAttribArray(loc);
    gl.vertexAttribPointer(loc, size, gl.FLOAT, false, 0, 0);
  };
  const vao = gl.createVertexArray();
  gl.bindVertexArray(vao);
  attrib("position", mesh.position, 3);
  attrib("normal", mesh.normal, 3);
  attrib("color", mesh.color, 3);
  attrib("uv", mesh.uv, 2);
  const ib = gl.createBuffer();
  gl.bindBuffer(gl.ELEMENT_ARRAY_BUFFER, ib);
  gl.bufferData(gl.ELEMENT_ARRAY_BUFFER, mesh.indices, gl.STATIC_DRAW);
  const textured = !!(mesh.image && mesh.uv);
  gl.uniform1i(gl.getUniformLocation(prog, "textured"), textured ? 1 : 0);
  if (textured) {
    const img = await createImageBitmap(mesh.image);
    const tex = gl.createTexture();
    gl.bindTexture(gl.TEXTURE_2D, tex);
    gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_MIN_FILTER, gl.LINEAR);
    gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_MAG_FILTER, gl.LINEAR);
    gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_WRAP_S, gl.CLAMP_TO_EDGE);
    gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_WRAP_T, gl.CLAMP_TO_EDGE);
    gl.texImage2D(gl.TEXTURE_2D, 0, gl.RGBA, gl.RGBA, gl.UNSIGNED_BYTE, img);
  }
  const radius = Math.hypot(mesh.max[0] - mesh.min[0], mesh.max[1] - mesh.min[1], mesh.max[2] - mesh.min[2]) / 2;
  const state = { yaw: 0.6, pitch: 0.65, dist: 2.2 * radius };
  const mvpLoc = gl.getUniformLocation(prog, "mvp");
  const draw = () => {
    gl.viewport(0, 0, canvas.width, canvas.height);
    gl.clearColor(1, 1, 1, 1);
    gl.enable(gl.DEPTH_TEST);
    gl.clear(gl.COLOR_BUFFER_BIT | gl.DEPTH_BUFFER_BIT);
    const p = perspective(0.8, canvas.width / canvas.height, radius / 100, radius * 10);
    gl.uniformMatrix4fv(mvpLoc, false, mat4Mul(p, view(state.yaw, state.pitch, state.dist)));
    gl.drawElements(gl.TRIANGLES, mesh.indices.length, gl.UNSIGNED_INT, 0);
  };
  let drag = null;
  canvas.addEventListener("mousedown", (e) => { drag = [e.clientX, e.clientY]; });
  window.addEventListener("mouseup", () => { drag = null; });
  window.addEventListener("mousemove", (e) => {
    if (!drag) return;
    state.yaw += (e.clientX - drag[0]) * 0.01;
    state.pitch = Math.max(0.05, Math.min(1.5, state.pitch + (e.clientY - drag[1]) * 0.01));
    drag = [e.clientX, e.clientY];
    draw();
  });
  canvas.addEventListener("wheel", (e) => {
    e.preventDefault();
    state.dist = Math.max(radius * 0.2, Math.min(radius * 8, state.dist * Math.exp(e.deltaY * 0.001)));
    draw();
  });
  draw();
  gl.finish();
  const px = new Uint8Array(canvas.width * canvas.height * 4);
  gl.readPixels(0, 0, canvas.width, canvas.height, gl.RGBA, gl.UNSIGNED_BYTE, px);
  let drawn = 0;
  for (let i = 0; i < px.length; i += 4) if (px[i] !== 255 || px[i + 1] !== 255 || px[i + 2] !== 255) drawn++;
  return drawn;
}
