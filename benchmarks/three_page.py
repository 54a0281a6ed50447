"""three.js from npm, with the project's three.js package, in headless Chromium: a page served to the browser from
disk (Playwright's routing, nothing from the network) that renders furnace planes and spheres through real
``MeshStandardMaterial`` / ``MeshPhysicalMaterial`` programs and reads the floats back (the tests' and
``benchmarks.three_package``'s).

Public objects: ``PACKAGE``, ``MODULES``, ``open_page``, ``furnace``, ``spheres``, ``load_gltf``, ``screenshot``,
``run_module``, ``gltf_document``, ``uv_sphere``.

The furnace: a uniform white environment (PMREM of a white background: radiance 1, irradiance π), an orthographic
camera (view direction (0, 0, 1) everywhere), and one plane per case tilted so that N·V = μ, stretched by 1/μ so that
it covers its cell, black (no diffuse) unless the case says otherwise, rendered into an RGBA32F target: the centre
pixel of a cell is the material's directional albedo as three.js's image-based light computes it.
"""

from __future__ import annotations

import base64
import json
import mimetypes
from pathlib import Path

import numpy as np

from benchmarks.browser import browser_page, page_bytes
from benchmarks.npm import NpmError, npm_unpacked
from handoff.three import THREE_VERSION

ROOT = Path(__file__).resolve().parents[1]
PACKAGE = ROOT / "luts" / "three"
ORIGIN = "http://fresnel.test"
CELL = 4
COLUMNS = 32

PAGE = """<!doctype html><html><body><canvas id="c"></canvas>
<script type="importmap">{"imports": {"three": "/three/build/three.module.js",
  "three/addons/": "/three/examples/jsm/", "fresnel-basis-three": "/fresnel-basis-three/index.js"}}</script>
<script type="module">
import * as THREE from 'three';
import { RectAreaLightUniformsLib } from 'three/addons/lights/RectAreaLightUniformsLib.js';
import { GLTFLoader } from 'three/addons/loaders/GLTFLoader.js';
import { RoomEnvironment } from 'three/addons/environments/RoomEnvironment.js';
import { applyFresnelBasis, FresnelBasisGLTFPlugin } from 'fresnel-basis-three';

RectAreaLightUniformsLib.init();

const loaded = [];

window.loadGltf = async (json) => {
  const loader = new GLTFLoader();
  loader.register((parser) => new FresnelBasisGLTFPlugin(parser));
  const gltf = await loader.parseAsync(JSON.stringify(json), '');
  loaded.length = 0;
  gltf.scene.traverse((o) => { if (o.isMesh) loaded.push(o.material); });
  return loaded.map((m) => ({ type: m.type, defines: m.defines, specularColor: m.specularColor && m.specularColor.toArray() }));
};

function material(c) {
  if (c.gltf !== undefined) return loaded[c.gltf];
  const m = c.physical ? new THREE.MeshPhysicalMaterial() : new THREE.MeshStandardMaterial();
  m.color.setRGB(...c.color, THREE.LinearSRGBColorSpace);
  m.metalness = c.metalness;
  m.roughness = c.roughness;
  if (c.ior !== undefined) m.ior = c.ior;
  if (c.extra !== undefined) Object.assign(m, c.extra);
  if (c.basis) applyFresnelBasis(m, c.basis);
  return m;
}

function renderer(width, height) {
  const r = new THREE.WebGLRenderer({ canvas: document.getElementById('c'), antialias: false });
  r.setPixelRatio(1);
  r.setSize(width, height, false);
  r.toneMapping = THREE.NoToneMapping;
  return r;
}

function whiteEnvironment(r) {
  const pmrem = new THREE.PMREMGenerator(r);
  const room = new THREE.Scene();
  room.background = new THREE.Color(1, 1, 1);
  return pmrem.fromScene(room).texture;
}

function readBack(r, scene, camera, width, height) {
  const target = new THREE.WebGLRenderTarget(width, height, { type: THREE.FloatType });
  r.setRenderTarget(target);
  r.render(scene, camera);
  const pixels = new Float32Array(width * height * 4);
  r.readRenderTargetPixels(target, 0, 0, width, height, pixels);
  r.setRenderTarget(null);
  return pixels;
}

function light(description) {
  if (description.kind === 'directional') {
    const l = new THREE.DirectionalLight(0xffffff, 1);
    l.position.set(...description.direction);
    return l;
  }
  const l = new THREE.RectAreaLight(0xffffff, 1, ...description.size);
  l.position.set(...description.position);
  l.lookAt(...description.lookAt);
  return l;
}

window.furnace = (cases, cell, columns, lighting) => {
  const rows = Math.ceil(cases.length / columns);
  const width = cell * columns, height = cell * rows;
  const r = renderer(width, height);
  const scene = new THREE.Scene();
  if (lighting) scene.add(light(lighting)); else scene.environment = whiteEnvironment(r);
  const camera = new THREE.OrthographicCamera(0, width, height, 0, 0.1, 4000);
  camera.position.z = 2000;
  const plane = new THREE.PlaneGeometry(cell, cell);
  cases.forEach((c, i) => {
    const mesh = new THREE.Mesh(plane, material(c));
    mesh.position.set((i % columns + 0.5) * cell, (Math.floor(i / columns) + 0.5) * cell, 0);
    mesh.rotation.x = -Math.acos(c.mu);
    mesh.scale.y = 1 / c.mu;
    scene.add(mesh);
  });
  const pixels = readBack(r, scene, camera, width, height);
  return cases.map((c, i) => {
    const x = (i % columns) * cell + cell / 2, y = Math.floor(i / columns) * cell + cell / 2;
    const at = 4 * (y * width + x);
    return [pixels[at], pixels[at + 1], pixels[at + 2]];
  });
};

window.spheres = (cases, size, environment) => {
  const width = size * cases.length, height = size;
  const r = renderer(width, height);
  const scene = new THREE.Scene();
  if (environment === 'white') scene.environment = whiteEnvironment(r);
  const camera = new THREE.OrthographicCamera(0, width, height, 0, 0.1, 4000);
  camera.position.z = 2000;
  const sphere = new THREE.SphereGeometry(size / 2 - 1, 128, 64);
  cases.forEach((c, i) => {
    const mesh = new THREE.Mesh(sphere, material(c));
    mesh.position.set((i + 0.5) * size, size / 2, 0);
    scene.add(mesh);
  });
  return readBack(r, scene, camera, width, height);
};
window.show = async (cases, size) => {
  const width = size * cases.length, height = size;
  const r = renderer(width, height);
  r.outputColorSpace = THREE.SRGBColorSpace;
  r.toneMapping = THREE.NeutralToneMapping;
  const scene = new THREE.Scene();
  scene.background = new THREE.Color(0.18, 0.18, 0.18);
  scene.environment = new THREE.PMREMGenerator(r).fromScene(new RoomEnvironment(), 0.02).texture;
  const camera = new THREE.PerspectiveCamera(14, width / height, 1, 100);
  camera.position.set(0, 0, 12);
  const sphere = new THREE.SphereGeometry(1, 128, 64);
  cases.forEach((c, i) => {
    const mesh = new THREE.Mesh(sphere, material(c));
    mesh.position.set((i - (cases.length - 1) / 2) * 2.2, 0, 0);
    scene.add(mesh);
  });
  r.render(scene, camera);
};
window.ready = true;
</script></body></html>
"""


#: Modules served at /modules/NAME.js (the tests run README's snippet through it).
MODULES: dict[str, str] = {}


def _route(route):
    path = route.request.url[len(ORIGIN) :].split("?")[0]
    if path == "/index.html":
        return route.fulfill(status=200, content_type="text/html", body=PAGE)
    if path.startswith("/modules/") and path[len("/modules/") : -len(".js")] in MODULES:
        return route.fulfill(status=200, content_type="text/javascript", body=MODULES[path[9:-3]])
    for prefix, folder in (("/three/", npm_unpacked("three", THREE_VERSION)), ("/fresnel-basis-three/", PACKAGE)):
        if path.startswith(prefix):
            file = (folder / path[len(prefix) :]).resolve()
            if file.is_relative_to(folder.resolve()) and file.is_file():
                kind = "text/javascript" if file.suffix == ".js" else mimetypes.guess_type(file.name)[0] or "text/plain"
                return route.fulfill(status=200, content_type=kind, body=file.read_bytes())
    return route.fulfill(status=404, body=f"not served: {path}")


def open_page(browser, missing=None):
    """(page with three.js and the package loaded, its console messages); ``missing(what)`` is called where npm
    cannot fetch three.js (the tests skip, or fail under ``CI=true``; by default it raises)."""
    try:
        npm_unpacked("three", THREE_VERSION)
    except NpmError as error:
        if missing is None:
            raise
        missing(str(error))
    page, messages = browser_page(browser)
    page.route(f"{ORIGIN}/**", _route)
    page.goto(f"{ORIGIN}/index.html")
    page.wait_for_function("window.ready === true", timeout=60_000)
    return page, messages


def furnace(page, cases: list[dict], lighting: dict | None = None) -> np.ndarray:
    """(len(cases), 3) of the furnace's read-back, one case a dict: ``mu``, ``roughness``, ``metalness``, ``color``
    (linear RGB), ``physical`` (MeshPhysicalMaterial), ``ior``, ``extra`` (more of the material's properties, set as
    they are), ``basis`` (applyFresnelBasis's options; absent: stock
    three.js), or ``gltf``: the index of a material :func:`load_gltf` loaded. ``lighting``: in place of the white environment, one light, ``{"kind": "directional", "direction":
    [x, y, z]}`` (intensity 1) or ``{"kind": "rect", "position", "size": [w, h], "lookAt"}``; the plane of case i
    is centred at ((i mod COLUMNS + ½) CELL, (⌊i / COLUMNS⌋ + ½) CELL, 0) with normal (0, √(1 − μ²), μ)."""
    return np.array(page.evaluate(f"window.furnace({json.dumps(cases)}, {CELL}, {COLUMNS}, {json.dumps(lighting)})"))


def spheres(page, cases: list[dict], size: int, environment: str = "white") -> np.ndarray:
    """(size, size × len(cases), 4) of spheres side by side, row 0 at the bottom."""
    expression = f"window.spheres({json.dumps(cases)}, {size}, {json.dumps(environment)})"
    values = np.frombuffer(page_bytes(page, expression), dtype="<f4").astype(np.float64)
    return values.reshape(size, size * len(cases), 4)


def load_gltf(page, document: dict) -> list[dict]:
    """Load a glTF document with GLTFLoader and the package's plugin; its meshes' materials (type, defines,
    specularColor), which furnace cases name by index (``{"gltf": i, "mu": …}``)."""
    return page.evaluate(f"window.loadGltf({json.dumps(document)})")


def screenshot(page, cases: list[dict], size: int) -> bytes:
    """PNG of spheres side by side in three.js's RoomEnvironment (sRGB, neutral tone mapping), one per case."""
    page.set_viewport_size({"width": size * len(cases), "height": size})
    page.evaluate(f"window.show({json.dumps(cases)}, {size})")
    return page.locator("#c").screenshot()


def run_module(page, name: str, source: str):
    """Import ``source`` as the ES module /modules/NAME.js in the page (three.js and the package resolve as in an app)
    and return its exported ``result`` (JSON-ready), if any."""
    MODULES[name] = source
    return page.evaluate(f"import('/modules/{name}.js').then((module) => module.result ?? null)")


def gltf_document(meshes: list[tuple[np.ndarray, np.ndarray | None, np.ndarray | None]], materials: list[dict]) -> dict:
    """A glTF 2.0 document with one buffer embedded: mesh i = (positions (N, 3), normals (N, 3) or None, triangle
    indices (M, 3) or None) with material i, one node each."""
    chunks, views, accessors, primitives = [], [], [], []
    offset = 0
    for positions, normals, indices in meshes:
        attributes = {}
        for name, values, kind in (("POSITION", positions, 5126), ("NORMAL", normals, 5126), (None, indices, 5125)):
            if values is None:
                continue
            data = np.ascontiguousarray(values, dtype="<f4" if kind == 5126 else "<u4").tobytes()
            views.append({"buffer": 0, "byteOffset": offset, "byteLength": len(data)})
            accessor = {
                "bufferView": len(views) - 1,
                "componentType": kind,
                "count": int(values.size // (3 if name else 1)),
            }
            accessor["type"] = "VEC3" if name else "SCALAR"
            if name == "POSITION":
                accessor.update(min=np.min(values, axis=0).tolist(), max=np.max(values, axis=0).tolist())
            accessors.append(accessor)
            chunks.append(data)
            offset += len(data)
            if name:
                attributes[name] = len(accessors) - 1
        primitive = {"attributes": attributes, "material": len(primitives)}
        if indices is not None:
            primitive["indices"] = len(accessors) - 1
        primitives.append(primitive)
    buffer = b"".join(chunks)
    return {
        "asset": {"version": "2.0"},
        "extensionsUsed": ["KHR_materials_specular"],
        "buffers": [{"uri": "data:application/octet-stream;base64," + base64.b64encode(buffer).decode("ascii"),
                     "byteLength": len(buffer)}],
        "bufferViews": views,
        "accessors": accessors,
        "materials": materials,
        "meshes": [{"primitives": [primitive]} for primitive in primitives],
        "nodes": [{"mesh": i} for i in range(len(primitives))],
        "scenes": [{"nodes": list(range(len(primitives)))}],
        "scene": 0,
    }  # fmt: skip


def uv_sphere(rows: int = 32, columns: int = 64) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(positions, normals, indices) of a unit sphere."""
    theta, phi = np.meshgrid(np.linspace(0, np.pi, rows + 1), np.linspace(0, 2 * np.pi, columns + 1), indexing="ij")
    points = np.stack([np.sin(theta) * np.cos(phi), np.cos(theta), np.sin(theta) * np.sin(phi)], axis=-1).reshape(-1, 3)
    i, j = np.meshgrid(np.arange(rows), np.arange(columns), indexing="ij")
    a, b = i * (columns + 1) + j, (i + 1) * (columns + 1) + j
    indices = np.stack([np.stack([a, b, a + 1], -1), np.stack([a + 1, b, b + 1], -1)], axis=2).reshape(-1, 3)
    return points, points, indices
