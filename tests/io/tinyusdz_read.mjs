// Reads a USD file with TinyUSDZ (the npm package `tinyusdz`, a WebAssembly build) and prints
// what an independent reader found, as JSON: the layer's metadata, each mesh's prim path,
// point and face counts and first point (the composed stage), and each mesh's `points` time
// codes (the layer as TinyUSDZ prints it back).
// Usage: node tinyusdz_read.mjs <dir holding tinyusdz.js and tinyusdz.wasm> <file.usda>
import fs from 'fs';
import path from 'path';

const [moduleDir, usdPath] = process.argv.slice(2);
const realProcess = globalThis.process;
// The package is built for browsers only: let its loader see a browser (a window, no
// process) and hand it the wasm bytes, so that it needs neither fetch nor node's own paths.
globalThis.window = globalThis;
const wasmBinary = fs.readFileSync(path.join(moduleDir, 'tinyusdz.wasm'));
Object.defineProperty(globalThis, 'process', { value: undefined, configurable: true, writable: true });
let native;
try {
  const init = (await import(path.join(moduleDir, 'tinyusdz.js'))).default;
  native = await init({ wasmBinary });
} finally {
  globalThis.process = realProcess;
}

const bytes = fs.readFileSync(usdPath);
const result = { loaded: false, error: '', metadata: {}, meshes: [] };
const stage = new native.TinyUSDZLoaderNative();
if (!stage.loadFromBinary(bytes, usdPath)) {
  result.error = String(stage.error());
  console.log(JSON.stringify(result));
  process.exit(0);
}
result.loaded = true;
for (let i = 0; i < stage.numMeshes(); ++i) {
  const m = stage.getMesh(i);
  result.meshes.push({
    path: m.absPath,
    name: m.primName,
    points: m.points.length / 3,
    face_vertex_counts: m.faceVertexCounts.length,
    face_vertex_indices: m.faceVertexIndices.length,
    first_point: Array.from(m.points.slice(0, 3)),
    time_codes: [],
  });
}

// Time samples: TinyUSDZ's own text of the layer it parsed. Mesh blocks in order; within
// each, the keys of its points.timeSamples dictionary.
const layer = new native.TinyUSDZLoaderNative();
if (!layer.loadAsLayerFromBinary(bytes, usdPath)) {
  result.loaded = false;
  result.error = String(layer.error());
} else {
  const text = layer.layerToString();
  for (const key of ['metersPerUnit', 'upAxis', 'startTimeCode', 'endTimeCode', 'timeCodesPerSecond', 'framesPerSecond', 'defaultPrim']) {
    const found = text.match(new RegExp('^\\s*' + key + ' = "?([^"\\n]*)"?$', 'm'));
    if (found) result.metadata[key] = found[1];
  }
  const meshes = text.split(/def Mesh "/).slice(1);
  meshes.forEach((block, i) => {
    const name = block.slice(0, block.indexOf('"'));
    const samples = block.split('points.timeSamples = {')[1];
    const mesh = result.meshes.find((m) => m.name === name);
    if (!mesh || samples === undefined) return;
    const body = samples.slice(0, samples.indexOf('\n        }'));
    mesh.time_codes = [...body.matchAll(/^\s*([-0-9.e+]+): \[/gm)].map((s) => Number(s[1]));
  });
}
console.log(JSON.stringify(result));
