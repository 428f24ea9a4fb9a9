#!/usr/bin/env node
// Pictures of glTF files in a real viewer: three.js (WebGL) in headless Chromium, side by side,
// all from one camera, lit only by an image-based environment (three.js applies an
// occlusionTexture to indirect light only, so that is where baked AO shows).
//
// Usage: node viewer-shot.js --modules DIR --out PNG [--width W] [--height H]
//                            [--view AZIMUTH,ELEVATION] [--label TEXT]... FILE.glb|FILE.gltf...
//   --modules  the folder with node_modules/three and node_modules/playwright-core
//              (scripts/viewer-pictures.sh installs them into build/tools/viewer)
//   --view     camera direction in degrees around +Y and above the horizon (default 35,20)
// Every file gets an equal share of the width; the camera frames the first file's bounds.
// Exits non-zero with one line naming the problem when a model does not load or WebGL fails.
'use strict';
const fs = require('fs');
const http = require('http');
const path = require('path');

function die(message) {
  console.error(`viewer-shot: ${message}`);
  process.exit(1);
}

const args = process.argv.slice(2);
const options = { width: 1600, height: 700, view: [35, 20], labels: [], files: [] };
for (let i = 0; i < args.length; ++i) {
  const a = args[i];
  const value = () => (i + 1 < args.length ? args[++i] : die(`${a} needs a value`));
  if (a === '--modules') options.modules = value();
  else if (a === '--out') options.out = value();
  else if (a === '--width') options.width = parseInt(value(), 10);
  else if (a === '--height') options.height = parseInt(value(), 10);
  else if (a === '--view') options.view = value().split(',').map(Number);
  else if (a === '--label') options.labels.push(value());
  else options.files.push(path.resolve(a));
}
if (!options.modules || !options.out || options.files.length === 0) die('usage: --modules DIR --out PNG FILE...');
const three = path.join(options.modules, 'node_modules', 'three');
if (!fs.existsSync(three)) die(`three.js is not in ${options.modules}: run scripts/viewer-pictures.sh`);
for (const f of options.files) if (!fs.existsSync(f)) die(`${f}: no such file`);
const { chromium } = require(path.join(options.modules, 'node_modules', 'playwright-core'));

const page_html = `<!doctype html><html><head><meta charset="utf-8">
<style>html,body{margin:0;background:#2e3440;overflow:hidden}
.label{position:absolute;top:10px;color:#e5e9f0;font:20px sans-serif;text-align:center}</style>
<script type="importmap">{"imports":{"three":"/three/build/three.module.js","three/addons/":"/three/examples/jsm/"}}</script>
</head><body><script type="module">
import * as THREE from 'three';
import { GLTFLoader } from 'three/addons/loaders/GLTFLoader.js';
import { RoomEnvironment } from 'three/addons/environments/RoomEnvironment.js';
const config = ${JSON.stringify({ count: options.files.length, width: options.width, height: options.height,
                                  view: options.view, labels: options.labels })};
try {
  const renderer = new THREE.WebGLRenderer({ antialias: true, preserveDrawingBuffer: true });
  renderer.setSize(config.width, config.height);
  renderer.setScissorTest(true);
  renderer.toneMapping = THREE.ACESFilmicToneMapping;
  document.body.appendChild(renderer.domElement);
  const pmrem = new THREE.PMREMGenerator(renderer);
  const environment = pmrem.fromScene(new RoomEnvironment(), 0.04).texture;
  const loader = new GLTFLoader();
  const scenes = [];
  for (let i = 0; i < config.count; ++i) {
    const gltf = await loader.loadAsync('/model/' + i + '/file');
    const scene = new THREE.Scene();
    scene.background = new THREE.Color(0x2e3440);
    scene.environment = environment;
    scene.add(gltf.scene);
    scenes.push(scene);
  }
  const box = new THREE.Box3().setFromObject(scenes[0]);
  const centre = box.getCenter(new THREE.Vector3());
  const radius = box.getSize(new THREE.Vector3()).length() / 2;
  const w = config.width / config.count;
  const camera = new THREE.PerspectiveCamera(35, w / config.height, radius / 100, radius * 100);
  const az = config.view[0] * Math.PI / 180, el = config.view[1] * Math.PI / 180;
  // The bounding sphere fills the narrower of the two fields of view, less a margin.
  const vfov = camera.fov * Math.PI / 180, hfov = 2 * Math.atan(Math.tan(vfov / 2) * camera.aspect);
  const distance = radius / Math.sin(Math.min(vfov, hfov) / 2) * 0.82;
  camera.position.set(centre.x + distance * Math.cos(el) * Math.sin(az), centre.y + distance * Math.sin(el),
                      centre.z + distance * Math.cos(el) * Math.cos(az));
  camera.lookAt(centre);
  scenes.forEach((scene, i) => {
    renderer.setViewport(i * w, 0, w, config.height);
    renderer.setScissor(i * w, 0, w, config.height);
    renderer.render(scene, camera);
    if (config.labels[i]) {
      const label = document.createElement('div');
      label.className = 'label';
      label.style.left = (i * w) + 'px';
      label.style.width = w + 'px';
      label.textContent = config.labels[i];
      document.body.appendChild(label);
    }
  });
  window.exaoDone = 'ok';
} catch (e) {
  window.exaoDone = 'error: ' + (e && e.message ? e.message : e);
}
</script></body></html>`;

const types = { '.js': 'text/javascript', '.glb': 'model/gltf-binary', '.gltf': 'model/gltf+json', '.bin': 'application/octet-stream',
                '.png': 'image/png', '.jpg': 'image/jpeg', '.html': 'text/html' };
// /three/... from three's package; /model/<i>/file is a model, /model/<i>/<name> a file beside it.
const server = http.createServer((req, res) => {
  const url = decodeURIComponent(req.url.split('?')[0]);
  let file = null;
  if (url === '/') {
    res.writeHead(200, { 'content-type': 'text/html' });
    res.end(page_html);
    return;
  }
  if (url.startsWith('/three/')) file = path.join(three, path.normalize(url.slice(7)).replace(/^(\.\.[/\\])+/, ''));
  const m = url.match(/^\/model\/(\d+)\/(.+)$/);
  if (m && Number(m[1]) < options.files.length) {
    const model = options.files[Number(m[1])];
    file = m[2] === 'file' ? model : path.join(path.dirname(model), path.normalize(m[2]).replace(/^(\.\.[/\\])+/, ''));
  }
  if (!file || !fs.existsSync(file) || !fs.statSync(file).isFile()) {
    res.writeHead(404);
    res.end();
    return;
  }
  res.writeHead(200, { 'content-type': types[path.extname(file).toLowerCase()] || 'application/octet-stream' });
  fs.createReadStream(file).pipe(res);
});

(async () => {
  await new Promise((resolve) => server.listen(0, '127.0.0.1', resolve));
  const port = server.address().port;
  const browser = await chromium.launch({
    executablePath: process.env.CHROMIUM || '/usr/bin/chromium',
    // No GPU here: WebGL runs on SwiftShader, Chromium's software renderer.
    args: ['--no-sandbox', '--disable-gpu', '--use-angle=swiftshader', '--enable-unsafe-swiftshader', '--ignore-gpu-blocklist',
           '--disable-quic', '--no-first-run', '--disable-background-networking', '--disable-component-update',
           '--disable-sync'],
  });
  try {
    const page = await browser.newPage({ viewport: { width: options.width, height: options.height } });
    page.on('console', (m) => { if (m.type() === 'error') console.error(`viewer-shot: page: ${m.text()}`); });
    await page.goto(`http://127.0.0.1:${port}/`);
    await page.waitForFunction(() => window.exaoDone !== undefined, null, { timeout: 300000 });
    const done = await page.evaluate(() => window.exaoDone);
    if (done !== 'ok') die(done);
    const tmp = options.out + '.tmp.png';
    await page.screenshot({ path: tmp });
    fs.renameSync(tmp, options.out);  // a half-written picture never replaces a good one
    console.log(`-> ${options.out}`);
  } finally {
    await browser.close();
    server.close();
  }
})().catch((e) => die(e.message.split('\n')[0]));
