// The look-development page of fresnel-basis (served by `fresnel-lut view`, fresnel_lut/view.py).
//
// WebGL 2 runs the shipped include verbatim (luts/fresnel_basis.glsl)
// on the shipped tables as half-float KTX2, with the page's own shaders (view.glsl): a unit sphere under the
// renderer's studio or the user's equirectangular map (prefiltered here on the GPU), a point light and a rectangular
// light; four pictures (Schlick's split sum, the basis', the basis' with multiple scattering, and a Monte-Carlo
// reference of the exact BRDF with the exact curve, accumulated over frames) and their ΔE2000 against the reference.
// window.fresnelView is the page's interface for scripts (the tests drive the controls and read the float targets).
"use strict";

(() => {
  const MODES = ["schlick", "basis", "multiple", "reference"];
  const KINDS = ["preset", "nk", "gulbrandsen", "f82tint"];
  const VIEWS = ["gallery", "single", "split", "difference", "delta-e"];
  const CAPTIONS = {
    schlick: "Schlick split sum",
    basis: "basis split sum",
    multiple: "basis + multiple scattering",
    reference: "reference",
  };
  const UNITS = { basisLut: 0, schlickLut: 1, ltcLut: 2, curve: 3, map: 4, prefiltered: 5, sum: 6, squares: 7 };
  const IMAGE_UNITS = [8, 9, 10]; // Schlick, basis, basis + MS pictures, read by the display and the statistics
  const PREFILTER_SAMPLES = 512;
  const MAX_REFERENCE_SAMPLES = 1 << 16; // float32 sums stay well inside their precision
  const $ = (id) => document.getElementById(id);
  const parameters = new URLSearchParams(location.search);

  let resolveReady, rejectReady;
  const ready = new Promise((resolve, reject) => {
    resolveReady = resolve;
    rejectReady = reject;
  });
  const api = { ready };
  window.fresnelView = api;

  function showError(message) {
    const line = $("error");
    line.textContent = String(message).split("\n")[0];
    line.hidden = false;
    $("status").textContent = "The page stopped.";
  }

  async function fetched(name, kind) {
    const response = await fetch(name);
    if (!response.ok) throw new Error(`${name}: the server answered ${response.status}`);
    if (kind === "json") return response.json();
    if (kind === "text") return response.text();
    return response.arrayBuffer();
  }

  // KTX2 (Khronos 2.0 specification §3): one level of VK_FORMAT_R16G16B16A16_SFLOAT, no supercompression.
  function parseKtx2(buffer, name) {
    const bytes = new Uint8Array(buffer);
    const identifier = [0xab, 0x4b, 0x54, 0x58, 0x20, 0x32, 0x30, 0xbb, 0x0d, 0x0a, 0x1a, 0x0a];
    if (bytes.length < 104 || identifier.some((byte, i) => bytes[i] !== byte)) {
      throw new Error(`${name} is not a KTX2 file`);
    }
    const data = new DataView(buffer);
    const u32 = (offset) => data.getUint32(offset, true);
    const u64 = (offset) => Number(data.getBigUint64(offset, true));
    const [format, width, height, supercompression] = [u32(12), u32(20), u32(24), u32(44)];
    if (format !== 97 || supercompression !== 0) {
      throw new Error(`${name} is not an uncompressed RGBA16F KTX2 (format ${format})`);
    }
    const keys = {};
    const decoder = new TextDecoder();
    for (let offset = u32(56), end = u32(56) + u32(60); offset + 4 <= end; ) {
      const length = u32(offset);
      const entry = bytes.subarray(offset + 4, offset + 4 + length);
      const zero = entry.indexOf(0);
      keys[decoder.decode(entry.subarray(0, zero))] = decoder.decode(entry.subarray(zero + 1, length - 1));
      offset += 4 + length + ((4 - (length % 4)) % 4);
    }
    const [levelOffset, levelLength] = [u64(80), u64(88)];
    if (levelLength !== width * height * 8 || levelOffset + levelLength > bytes.length) {
      throw new Error(`${name} is truncated`);
    }
    return { width, height, keys, texels: new Uint16Array(buffer, levelOffset, width * height * 4) };
  }

  function floatTexture(gl, width, height, data, filter) {
    const texture = gl.createTexture();
    gl.bindTexture(gl.TEXTURE_2D, texture);
    gl.texImage2D(gl.TEXTURE_2D, 0, gl.RGBA32F, width, height, 0, gl.RGBA, gl.FLOAT, data || null);
    for (const [key, value] of [
      [gl.TEXTURE_MIN_FILTER, filter || gl.NEAREST],
      [gl.TEXTURE_MAG_FILTER, filter || gl.NEAREST],
      [gl.TEXTURE_WRAP_S, gl.CLAMP_TO_EDGE],
      [gl.TEXTURE_WRAP_T, gl.CLAMP_TO_EDGE],
    ]) {
      gl.texParameteri(gl.TEXTURE_2D, key, value);
    }
    return texture;
  }

  // A table as the includes read it: RGBA16F, rows in file order (v = the file's row), bilinear, clamp to edge,
  // one level (the includes fetch level 0).
  function tableTexture(gl, table) {
    const texture = gl.createTexture();
    gl.bindTexture(gl.TEXTURE_2D, texture);
    gl.texImage2D(gl.TEXTURE_2D, 0, gl.RGBA16F, table.width, table.height, 0, gl.RGBA, gl.HALF_FLOAT, table.texels);
    gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_MIN_FILTER, gl.LINEAR);
    gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_MAG_FILTER, gl.LINEAR);
    gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_WRAP_S, gl.CLAMP_TO_EDGE);
    gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_WRAP_T, gl.CLAMP_TO_EDGE);
    return texture;
  }

  function target(gl, texture) {
    const framebuffer = gl.createFramebuffer();
    gl.bindFramebuffer(gl.FRAMEBUFFER, framebuffer);
    gl.framebufferTexture2D(gl.FRAMEBUFFER, gl.COLOR_ATTACHMENT0, gl.TEXTURE_2D, texture, 0);
    if (gl.checkFramebufferStatus(gl.FRAMEBUFFER) !== gl.FRAMEBUFFER_COMPLETE) {
      throw new Error("This browser cannot render into a float texture (RGBA32F framebuffer incomplete).");
    }
    return framebuffer;
  }

  function compile(gl, name, fragmentSource) {
    const shader = (type, source) => {
      const object = gl.createShader(type);
      gl.shaderSource(object, source);
      gl.compileShader(object);
      if (!gl.getShaderParameter(object, gl.COMPILE_STATUS)) {
        const log = (gl.getShaderInfoLog(object) || "").trim().split("\n")[0];
        throw new Error(`the ${name} shader does not compile here: ${log}`);
      }
      return object;
    };
    const program = gl.createProgram();
    gl.attachShader(program, shader(gl.VERTEX_SHADER, "#version 300 es\nin vec2 p;\nvoid main() { gl_Position = vec4(p, 0.0, 1.0); }\n"));
    gl.attachShader(program, shader(gl.FRAGMENT_SHADER, fragmentSource));
    gl.bindAttribLocation(program, 0, "p");
    gl.linkProgram(program);
    if (!gl.getProgramParameter(program, gl.LINK_STATUS)) {
      throw new Error(`the ${name} shader does not link here: ${gl.getProgramInfoLog(program)}`);
    }
    const locations = {};
    const uniform = (key) => {
      if (!(key in locations)) locations[key] = gl.getUniformLocation(program, key);
      return locations[key];
    };
    return { program, uniform };
  }

  // The sections of view.glsl: "//! name" starts one; "common" goes before every other.
  function sections(text) {
    const found = {};
    let name = null;
    for (const line of text.split("\n")) {
      const start = /^\/\/! (\w+)/.exec(line);
      if (start) {
        name = start[1];
        found[name] = "";
      } else if (name) {
        found[name] += line + "\n";
      }
    }
    return found;
  }

  const srgbDecode = (v) => (v <= 0.04045 ? v / 12.92 : Math.pow((v + 0.055) / 1.055, 2.4));
  const srgbEncode = (v) => (v <= 0.0031308 ? 12.92 * v : 1.055 * Math.pow(v, 1 / 2.4) - 0.055);

  function colourControl(name) {
    const picker = $(name);
    const fields = ["r", "g", "b"].map((channel) => $(`${name}-${channel}`));
    const toPicker = () => {
      const hex = fields.map((field) => {
        const value = Math.min(Math.max(Number(field.value) || 0, 0), 1);
        return Math.round(srgbEncode(value) * 255).toString(16).padStart(2, "0");
      });
      picker.value = `#${hex.join("")}`;
    };
    picker.addEventListener("input", () => {
      const hex = picker.value.slice(1);
      fields.forEach((field, i) => {
        field.value = srgbDecode(parseInt(hex.slice(2 * i, 2 * i + 2), 16) / 255).toFixed(4);
      });
    });
    fields.forEach((field) => field.addEventListener("input", toPicker));
    return { set: (values) => { fields.forEach((field, i) => { field.value = String(values[i]); }); toPicker(); } };
  }

  // A number field's value, clamped to its min and max; an empty or bad entry reads as its last good value.
  function fieldValue(field) {
    const value = Number(field.value);
    if (field.value.trim() === "" || !Number.isFinite(value)) {
      field.setCustomValidity("a number");
      return Number(field.dataset.good ?? field.defaultValue ?? 0);
    }
    field.setCustomValidity("");
    const low = field.min === "" ? -Infinity : Number(field.min);
    const high = field.max === "" ? Infinity : Number(field.max);
    const clamped = Math.min(Math.max(value, low), high);
    field.dataset.good = String(clamped);
    return clamped;
  }
  const triple = (name) => ["r", "g", "b"].map((channel) => fieldValue($(`${name}-${channel}`)));

  async function start() {
    const canvas = $("canvas");
    const gl = canvas.getContext("webgl2", { antialias: false, preserveDrawingBuffer: true, premultipliedAlpha: false });
    if (!gl) throw new Error("This page needs WebGL 2, which this browser does not offer.");
    if (!gl.getExtension("EXT_color_buffer_float")) {
      throw new Error("This page needs float render targets (EXT_color_buffer_float), which this browser's WebGL 2 lacks.");
    }
    const [config, include, pageShaders, ...tables] = await Promise.all([
      fetched("config.json", "json"),
      fetched("shaders/fresnel_basis.glsl", "text"),
      fetched("view.glsl", "text"),
      ...["ggx_basis_rgba", "ggx_schlick_rgba", "ggx_ltc"].map((name) => fetched(`tables/${name}.ktx2`, "buffer")),
    ]);
    const [basisTable, schlickTable, ltcTable] = tables.map((buffer, i) =>
      parseKtx2(buffer, ["ggx_basis_rgba", "ggx_schlick_rgba", "ggx_ltc"][i] + ".ktx2"));
    $("asset-link").hidden = !config.three;
    const includeHash = (/FRESNEL_BASIS_HASH = 0x([0-9a-f]+)u/.exec(include) || [])[1];
    const tableHash = basisTable.keys["fresnel:basis_hash"] || "";
    if (!includeHash || !tableHash.startsWith(includeHash) || tableHash !== config.basis_hash) {
      throw new Error(`ggx_basis_rgba.ktx2 belongs to basis ${tableHash || "(none)"}, the shader include to ` +
        `${includeHash || "(none)"}… and the presets to ${config.basis_hash}: a table from another basis ` +
        "(rebuild the tables and the include together: fresnel-lut build)");
    }
    const size = Math.max(8, Math.min(2048, Number(parameters.get("size")) || config.size));
    const samplesPerFrame = Math.max(1, Math.min(256, Number(parameters.get("spp")) || 4));

    const head = "#version 300 es\nprecision highp float;\nprecision highp int;\nprecision highp sampler2D;\n";
    const parts = sections(pageShaders);
    const programs = {};
    for (const name of ["shade", "prefilter", "display", "statistics"]) {
      programs[name] = compile(gl, name, head + include + parts.common + parts[name]);
    }

    const quad = gl.createBuffer();
    gl.bindBuffer(gl.ARRAY_BUFFER, quad);
    gl.bufferData(gl.ARRAY_BUFFER, new Float32Array([-1, -1, 1, -1, -1, 1, 1, 1]), gl.STATIC_DRAW);
    gl.enableVertexAttribArray(0);
    gl.vertexAttribPointer(0, 2, gl.FLOAT, false, 0, 0);

    const textures = {
      basisLut: tableTexture(gl, basisTable),
      schlickLut: tableTexture(gl, schlickTable),
      ltcLut: tableTexture(gl, ltcTable),
      curve: floatTexture(gl, 1, 1, new Float32Array(4)),
      map: floatTexture(gl, 1, 1, new Float32Array(4)),
      prefiltered: floatTexture(gl, 1, 1, new Float32Array(4)),
    };
    const images = [0, 1, 2].map(() => floatTexture(gl, size, size));
    const imageTargets = images.map((texture) => target(gl, texture));
    const sums = [0, 1].map(() => floatTexture(gl, size, size));
    const squares = [0, 1].map(() => floatTexture(gl, size, size));
    const referenceTargets = [0, 1].map((i) => {
      const framebuffer = target(gl, sums[i]);
      gl.framebufferTexture2D(gl.FRAMEBUFFER, gl.COLOR_ATTACHMENT1, gl.TEXTURE_2D, squares[i], 0);
      return framebuffer;
    });
    const statisticsTexture = floatTexture(gl, size, size);
    const statisticsTarget = target(gl, statisticsTexture);
    let current = 0; // the reference's current sum and squares

    // the environment: the studio in closed form, or the user's map (mip levels stacked in one atlas)
    let environment = null;
    if (config.environment) {
      const { width, height, name } = config.environment;
      const pixels = new Float32Array(await fetched("environment.f32", "buffer"));
      if (pixels.length !== width * height * 4) throw new Error(`environment ${name}: ${pixels.length / 4} texels, not ${width} x ${height}`);
      const rows = [0];
      let level = pixels, w = width, h = height;
      const levels = [pixels];
      while (w > 1 && h > 1 && levels.length < 16) {
        const next = new Float32Array((w >> 1) * (h >> 1) * 4);
        for (let y = 0; y < h >> 1; ++y) {
          for (let x = 0; x < w >> 1; ++x) {
            const top = (2 * y * w + 2 * x) * 4, bottom = top + w * 4; // the 2 x 2 texels' first channels
            for (let c = 0; c < 4; ++c) {
              next[(y * (w >> 1) + x) * 4 + c] =
                0.25 * (level[top + c] + level[top + 4 + c] + level[bottom + c] + level[bottom + 4 + c]);
            }
          }
        }
        rows.push(rows[rows.length - 1] + h);
        [level, w, h] = [next, w >> 1, h >> 1];
        levels.push(next);
      }
      const atlasHeight = rows[rows.length - 1] + h;
      const atlas = new Float32Array(width * atlasHeight * 4);
      levels.forEach((data, l) => {
        const lw = Math.max(width >> l, 1);
        for (let y = 0; y < Math.max(height >> l, 1); ++y) {
          atlas.set(data.subarray(y * lw * 4, (y + 1) * lw * 4), ((rows[l] + y) * width) * 4);
        }
      });
      gl.deleteTexture(textures.map);
      textures.map = floatTexture(gl, width, atlasHeight, atlas);
      environment = { name, width, height, rows, levels: levels.length };
      $("environment-name").textContent = name;
    }

    // the controls
    const colours = Object.fromEntries(["reflectivity", "edge-tint", "f0", "tint"].map((name) => [name, colourControl(name)]));
    colours.reflectivity.set(config.figure2.reflectivity);
    colours["edge-tint"].set(config.figure2.edge_tint);
    colours.f0.set(triple("f0"));
    colours.tint.set(triple("tint"));
    $("roughness").value = String(config.figure2.roughness);
    for (const preset of config.presets) {
      const option = document.createElement("option");
      option.value = option.textContent = preset.name;
      $("preset").append(option);
    }
    $("preset").value = config.presets.some((p) => p.name === "Gold") ? "Gold" : config.presets[0].name;

    const state = {};
    let changed = true, prefilterStale = true, referenceCount = 0;
    function readControls() {
      const kind = $("kind").value;
      const before = JSON.stringify(state);
      state.kind = KINDS.includes(kind) ? kind : "gulbrandsen";
      state.preset = $("preset").value;
      state.roughness = fieldValue($("roughness"));
      $("roughness-value").textContent = state.roughness.toFixed(3);
      state.a = state.kind === "nk" ? triple("eta") : state.kind === "gulbrandsen" ? triple("reflectivity") : triple("f0");
      state.b = state.kind === "nk" ? triple("kappa") : state.kind === "gulbrandsen" ? triple("edge-tint") : triple("tint");
      state.lights = { environment: $("light-environment").checked, point: $("light-point").checked, rect: $("light-rect").checked };
      const view = VIEWS.includes($("view").value) ? $("view").value : "gallery";
      if (view !== state.view && (view === "difference" || view === "delta-e")) {
        $("difference-scale").value = view === "difference" ? "0.2" : "5"; // linear radiance, or ΔE2000
      }
      state.view = view;
      state.main = MODES.indexOf($("main").value);
      state.compare = MODES.indexOf($("compare").value);
      state.differenceScale = Math.max(fieldValue($("difference-scale")), 1e-3);
      for (const kindName of KINDS) {
        document.querySelectorAll(`.kind-${kindName}`).forEach((element) => { element.hidden = kindName !== state.kind; });
      }
      const material = JSON.stringify([state.kind, state.preset, state.roughness, state.a, state.b, state.lights]);
      if (material !== api.materialKey) {
        if (api.materialKey === undefined || JSON.parse(api.materialKey)[2] !== state.roughness) prefilterStale = true;
        api.materialKey = material;
        changed = true;
        referenceCount = 0;
        statisticsShown = -1;
      }
      if (before !== JSON.stringify(state)) layout();
    }
    function layout() {
      const gallery = state.view === "gallery";
      canvas.width = gallery ? 4 * size : size;
      canvas.height = size;
      const captions = gallery ? MODES.map((mode) => CAPTIONS[mode])
        : state.view === "single" ? [CAPTIONS[MODES[state.main]]]
        : state.view === "split" ? [CAPTIONS[MODES[state.main]], CAPTIONS[MODES[state.compare]]]
        : [`${state.view === "delta-e" ? "ΔE2000" : "|Δ|"} of ${CAPTIONS[MODES[state.main]]} and ${CAPTIONS[MODES[state.compare]]}`];
      $("captions").replaceChildren(...captions.map((text) => Object.assign(document.createElement("span"), { textContent: text })));
      $("legend").textContent = state.view === "difference" || state.view === "delta-e"
        ? `heat map: black 0, purple, orange, white ${state.differenceScale} (${state.view === "delta-e" ? "ΔE2000 of the tone-mapped pictures" : "largest channel, linear radiance"})`
        : "tone map: identity to 0.8, then x / (1 + x) on the excess (fresnel_lut.render.tone_map); sRGB";
    }

    function bindUnits() {
      for (const [name, unit] of Object.entries(UNITS)) {
        gl.activeTexture(gl.TEXTURE0 + unit);
        const texture = name === "sum" ? sums[current] : name === "squares" ? squares[current] : textures[name];
        gl.bindTexture(gl.TEXTURE_2D, texture);
      }
      IMAGE_UNITS.forEach((unit, i) => {
        gl.activeTexture(gl.TEXTURE0 + unit);
        gl.bindTexture(gl.TEXTURE_2D, images[i]);
      });
    }

    function setMaterial({ uniform }) {
      const preset = config.presets.find((p) => p.name === state.preset) || config.presets[0];
      gl.uniform1f(uniform("u_size"), size);
      gl.uniform1i(uniform("u_kind"), KINDS.indexOf(state.kind));
      gl.uniform3fv(uniform("u_a"), state.a);
      gl.uniform3fv(uniform("u_b"), state.b);
      ["u_presetR", "u_presetG", "u_presetB"].forEach((name, i) => gl.uniform4fv(uniform(name), preset.coefficients[i]));
      gl.uniform1f(uniform("u_roughness"), state.roughness);
      gl.uniform1i(uniform("u_lobes"), config.studio.sharpness.length);
      gl.uniform3fv(uniform("u_lobeAxis"), config.studio.axes.flat());
      gl.uniform1fv(uniform("u_lobeSharpness"), config.studio.sharpness);
      gl.uniform3fv(uniform("u_lobeAmplitude"), config.studio.amplitudes.flat());
      gl.uniformMatrix3fv(uniform("u_rgbToXyz"), true, config.colorimetry.rgb_to_xyz.flat());
      gl.uniform3fv(uniform("u_white"), config.colorimetry.white);
      for (const [name, unit] of Object.entries(UNITS)) gl.uniform1i(uniform(`u_${name}`), unit);
      ["u_schlick", "u_basis", "u_multiple"].forEach((name, i) => gl.uniform1i(uniform(name), IMAGE_UNITS[i]));
      gl.uniform1i(uniform("u_curve"), UNITS.curve);
      gl.uniform1i(uniform("u_atlas"), UNITS.map);
    }

    let curveOf = null;
    function uploadCurve() {
      const preset = config.presets.find((p) => p.name === state.preset) || config.presets[0];
      if (curveOf === preset.name) return;
      const rgba = new Float32Array(preset.curve.length / 3 * 4);
      for (let i = 0; i < preset.curve.length / 3; ++i) {
        rgba.set(preset.curve.slice(3 * i, 3 * i + 3), 4 * i);
        rgba[4 * i + 3] = 1;
      }
      gl.deleteTexture(textures.curve);
      textures.curve = floatTexture(gl, rgba.length / 4, 1, rgba);
      curveOf = preset.name;
    }

    let prefilteredSize = [1, 1];
    function prefilter() {
      prefilterStale = false;
      if (!environment) return;
      const alpha = state.roughness * state.roughness;
      const lobe = Math.SQRT2 * Math.max(alpha, 1e-4); // the SG lobe's angular width
      const width = Math.min(environment.width, Math.max(32, 2 ** Math.ceil(Math.log2(8 * Math.PI / lobe))));
      prefilteredSize = [width, width / 2];
      gl.deleteTexture(textures.prefiltered);
      textures.prefiltered = floatTexture(gl, width, width / 2);
      const framebuffer = target(gl, textures.prefiltered);
      const { program, uniform } = programs.prefilter;
      gl.useProgram(program);
      bindUnits();
      setMaterial(programs.prefilter);
      gl.uniform2i(uniform("u_mapSize"), environment.width, environment.height);
      gl.uniform1i(uniform("u_levels"), environment.levels);
      gl.uniform1iv(uniform("u_levelRow"), Int32Array.from({ length: 16 }, (_, l) => environment.rows[Math.min(l, environment.rows.length - 1)]));
      gl.uniform1f(uniform("u_alpha"), alpha);
      gl.uniform1i(uniform("u_count"), PREFILTER_SAMPLES);
      gl.uniform2i(uniform("u_outputSize"), width, width / 2);
      gl.viewport(0, 0, width, width / 2);
      gl.drawBuffers([gl.COLOR_ATTACHMENT0]);
      gl.drawArrays(gl.TRIANGLE_STRIP, 0, 4);
      gl.deleteFramebuffer(framebuffer);
    }

    function shade(mode, samples) {
      const { program, uniform } = programs.shade;
      gl.useProgram(program);
      bindUnits();
      setMaterial(programs.shade);
      gl.uniform1i(uniform("u_mode"), mode);
      gl.uniform1i(uniform("u_environmentOn"), state.lights.environment ? 1 : 0);
      gl.uniform1i(uniform("u_pointOn"), state.lights.point ? 1 : 0);
      gl.uniform1i(uniform("u_rectOn"), state.lights.rect ? 1 : 0);
      gl.uniform1i(uniform("u_environmentKind"), environment ? 1 : 0);
      gl.uniform2i(uniform("u_mapSize"), environment ? environment.width : 1, environment ? environment.height : 1);
      gl.uniform2i(uniform("u_prefilteredSize"), ...prefilteredSize);
      gl.uniform3fv(uniform("u_pointDirection"), config.point_light.direction);
      gl.uniform1f(uniform("u_pointRadiance"), config.point_light.radiance);
      gl.uniform3fv(uniform("u_rectCorners"), config.rect_light.corners.flat());
      gl.uniform1f(uniform("u_rectRadiance"), config.rect_light.radiance);
      gl.uniform1i(uniform("u_samples"), samples || 0);
      gl.uniform1i(uniform("u_sampleBase"), referenceCount);
      gl.viewport(0, 0, size, size);
      if (mode < 3) {
        gl.bindFramebuffer(gl.FRAMEBUFFER, imageTargets[mode]);
        gl.drawBuffers([gl.COLOR_ATTACHMENT0]);
      } else {
        gl.bindFramebuffer(gl.FRAMEBUFFER, referenceTargets[1 - current]);
        gl.drawBuffers([gl.COLOR_ATTACHMENT0, gl.COLOR_ATTACHMENT1]);
      }
      gl.drawArrays(gl.TRIANGLE_STRIP, 0, 4);
      if (mode === 3) {
        current = 1 - current;
        referenceCount += samples;
      }
    }

    function clearReference() {
      for (const framebuffer of referenceTargets) {
        gl.bindFramebuffer(gl.FRAMEBUFFER, framebuffer);
        gl.drawBuffers([gl.COLOR_ATTACHMENT0, gl.COLOR_ATTACHMENT1]);
        gl.clearBufferfv(gl.COLOR, 0, [0, 0, 0, 0]);
        gl.clearBufferfv(gl.COLOR, 1, [0, 0, 0, 0]);
      }
      referenceCount = 0;
    }

    function display() {
      const { program, uniform } = programs.display;
      gl.bindFramebuffer(gl.FRAMEBUFFER, null);
      gl.viewport(0, 0, canvas.width, canvas.height);
      gl.useProgram(program);
      bindUnits();
      setMaterial(programs.display);
      gl.uniform1i(uniform("u_view"), VIEWS.indexOf(state.view));
      gl.uniform1i(uniform("u_main"), state.main);
      gl.uniform1i(uniform("u_compare"), state.compare);
      gl.uniform1f(uniform("u_differenceScale"), state.differenceScale);
      gl.drawArrays(gl.TRIANGLE_STRIP, 0, 4);
    }

    function readTarget(framebuffer, attachment) {
      const pixels = new Float32Array(size * size * 4);
      gl.bindFramebuffer(gl.FRAMEBUFFER, framebuffer);
      gl.readBuffer(attachment ?? gl.COLOR_ATTACHMENT0);
      gl.readPixels(0, 0, size, size, gl.RGBA, gl.FLOAT, pixels);
      gl.readBuffer(gl.COLOR_ATTACHMENT0);
      return pixels;
    }

    function statistics() {
      const { program } = programs.statistics;
      gl.bindFramebuffer(gl.FRAMEBUFFER, statisticsTarget);
      gl.drawBuffers([gl.COLOR_ATTACHMENT0]);
      gl.viewport(0, 0, size, size);
      gl.useProgram(program);
      bindUnits();
      setMaterial(programs.statistics);
      gl.drawArrays(gl.TRIANGLE_STRIP, 0, 4);
      const values = readTarget(statisticsTarget);
      const result = { samples: referenceCount };
      ["schlick", "basis", "multiple"].forEach((mode, c) => {
        let max = 0, sum = 0, count = 0;
        for (let i = 0; i < values.length; i += 4) {
          if (values[i + 3] > 0) {
            max = Math.max(max, values[i + c]);
            sum += values[i + c];
            count += 1;
          }
        }
        result[mode] = { max, mean: count ? sum / count : 0, pixels: count };
      });
      return result;
    }

    let statisticsShown = -1, lastStatistics = 0;
    function showNumbers(force) {
      const now = performance.now();
      if (!force && (referenceCount === statisticsShown || now - lastStatistics < 500)) return;
      lastStatistics = now;
      statisticsShown = referenceCount;
      const result = statistics();
      for (const mode of ["schlick", "basis", "multiple"]) {
        $(`${mode}-max`).textContent = result[mode].max.toFixed(2);
        $(`${mode}-mean`).textContent = result[mode].mean.toFixed(3);
      }
      const reference = readReference();
      $("reference-status").textContent = `reference: ${referenceCount} samples per pixel; its standard error, ` +
        `mean over the sphere: ${reference.meanSpread.toExponential(1)} (linear radiance)`;
      api.lastStatistics = result;
    }

    function readReference() {
      const sum = readTarget(referenceTargets[current], gl.COLOR_ATTACHMENT0);
      const sq = readTarget(referenceTargets[current], gl.COLOR_ATTACHMENT1);
      const mean = new Float32Array(sum.length), spread = new Float32Array(sum.length);
      let total = 0, count = 0;
      for (let i = 0; i < sum.length; i += 4) {
        const n = sum[i + 3];
        for (let c = 0; c < 3; ++c) {
          const m = n > 0 ? sum[i + c] / n : 0;
          mean[i + c] = m;
          spread[i + c] = n > 1 ? Math.sqrt(Math.max(sq[i + c] / n - m * m, 0) / (n - 1)) : 0;
          if (n > 0) { total += spread[i + c]; count += 1; }
        }
        mean[i + 3] = spread[i + 3] = n > 0 ? 1 : 0;
      }
      return { mean, spread, samples: referenceCount, meanSpread: count ? total / count : 0 };
    }

    let frameInterval = null, lastFrame = null;
    let settleWaiters = [];
    function frame(time) {
      try {
        readControls();
        if (changed) {
          uploadCurve();
          if (prefilterStale) prefilter();
          for (let mode = 0; mode < 3; ++mode) shade(mode);
          clearReference();
          changed = false;
        }
        if (referenceCount < Math.min(api.targetSamples, MAX_REFERENCE_SAMPLES)) {
          shade(3, Math.min(samplesPerFrame, api.targetSamples - referenceCount));
        }
        display();
        showNumbers(false);
        if (lastFrame !== null) {
          const interval = time - lastFrame;
          frameInterval = frameInterval === null ? interval : 0.9 * frameInterval + 0.1 * interval;
          $("timing").textContent = `frame interval ${frameInterval.toFixed(1)} ms (mean of the last frames); ` +
            `${samplesPerFrame} reference samples per pixel per frame at ${size} x ${size}`;
        }
        lastFrame = time;
        settleWaiters = settleWaiters.filter(({ samples, resolve }) => {
          if (referenceCount >= samples) { resolve(referenceCount); return false; }
          return true;
        });
        requestAnimationFrame(frame);
      } catch (error) {
        showError(error.message);
        settleWaiters.forEach(({ reject }) => reject(error));
      }
    }

    // Time per picture: each mode drawn once to warm up, then `repeats` times, each batch ended by a one-texel
    // readPixels (which waits for the draws; gl.finish() need not); wall clock per draw in ms
    function timeModes(repeats) {
      const result = {};
      const texel = new Float32Array(4);
      const draw = (mode) => {
        if (mode < 3) {
          shade(mode);
        } else {
          shade(3, 1);
          referenceCount -= 1;
          current = 1 - current; // the sum drawn into is scratch: the reference keeps its own
        }
      };
      const wait = (mode) => {
        gl.bindFramebuffer(gl.FRAMEBUFFER, mode < 3 ? imageTargets[mode] : referenceTargets[1 - current]);
        gl.readPixels(0, 0, 1, 1, gl.RGBA, gl.FLOAT, texel);
      };
      // five rounds with the modes alternated; each mode's fastest round (the machine's other load only slows)
      for (let round = 0; round < 5; ++round) {
        for (let mode = 0; mode < 4; ++mode) {
          draw(mode);
          wait(mode);
          const started = performance.now();
          for (let i = 0; i < repeats; ++i) draw(mode);
          wait(mode);
          const time = (performance.now() - started) / repeats;
          result[MODES[mode]] = Math.min(result[MODES[mode]] ?? Infinity, time);
        }
      }
      changed = true;
      return result;
    }

    Object.assign(api, {
      size,
      state,
      environment: environment && { ...environment },
      renderer: gl.getParameter(gl.RENDERER),
      targetSamples: Number(parameters.get("samples")) || 4096,
      // the float pictures, rows bottom first: "schlick", "basis", "multiple" (linear RGBA), or the reference's
      // mean and standard error
      readImage: (name) => Array.from(readTarget(imageTargets[MODES.indexOf(name)])),
      readReference: () => {
        const { mean, spread, samples } = readReference();
        return { mean: Array.from(mean), spread: Array.from(spread), samples };
      },
      // the canvas as shown (8-bit sRGB RGBA, rows bottom first), after the next frame
      readCanvas: () => new Promise((resolve) => requestAnimationFrame(() => requestAnimationFrame(() => {
        const pixels = new Uint8Array(canvas.width * canvas.height * 4);
        gl.bindFramebuffer(gl.FRAMEBUFFER, null);
        gl.readPixels(0, 0, canvas.width, canvas.height, gl.RGBA, gl.UNSIGNED_BYTE, pixels);
        resolve({ width: canvas.width, height: canvas.height, pixels: Array.from(pixels) });
      }))),
      statistics,
      timeModes,
      // resolves once the reference holds `samples` samples per pixel for the current controls, where it stays
      settle: (samples) => new Promise((resolve, reject) => {
        api.targetSamples = samples;
        settleWaiters.push({ samples, resolve, reject });
      }),
    });
    readControls();
    layout();
    $("status").textContent = `WebGL 2 on ${api.renderer}; basis ${config.basis_hash}; tables as half-float KTX2; ` +
      `${environment ? `environment ${environment.name} (${environment.width} x ${environment.height})` : "studio environment"}`;
    requestAnimationFrame(frame);
    resolveReady(api);
  }

  window.addEventListener("DOMContentLoaded", () => {
    start().catch((error) => {
      showError(error.message);
      rejectReady(error);
    });
  });
})();
