// 3D replay of recorded motion (sim/'s trajectory file, JSON lines; format in web_dashboard/README.md):
// bodies as capsules, boxes and spheres, the ground (with holes where terrain regions replace it),
// the terrain's boxes (tiles, flat patches, slopes) and the props (bar, box, blocks); play, pause,
// scrub, speed, camera orbit, props and terrain shown or hidden; with ?compare=ID a second trial
// side by side on the same clock. A trial may be written ID:NAME to show its trajectory artifact
// NAME (e.g. 12:trajectory_fast beside 12:trajectory, a get-up fast and slowed).
import * as THREE from './vendor/three.module.js';
import { OrbitControls } from './vendor/OrbitControls.js';

const params = new URLSearchParams(location.search);
const views_asked = [params.get('trial'), params.get('compare')].filter(Boolean).map(v => {
  const at = v.indexOf(':');
  return at < 0 ? { id: v, artifact: 'trajectory' } : { id: v.slice(0, at), artifact: v.slice(at + 1) };
});
const ids = views_asked.map(v => v.id);
const palette = [0x4e79a7, 0xf28e2b];
const width = ids.length > 1 ? 560 : 900, height = 520;

function geometry(g) {
  if (g.type === 'capsule') {  // three's capsule runs along y; ours along the local z axis
    const geo = new THREE.CapsuleGeometry(g.radius, 2 * g.half_length, 6, 12);
    geo.rotateX(Math.PI / 2);
    return geo;
  }
  if (g.type === 'box') return new THREE.BoxGeometry(2 * g.half_extents[0], 2 * g.half_extents[1], 2 * g.half_extents[2]);
  if (g.type === 'sphere') return new THREE.SphereGeometry(g.radius, 16, 12);
  throw new Error(`unknown geom type "${g.type}"`);
}

function place(object, pos = [0, 0, 0], quat = [1, 0, 0, 0]) {  // quaternions are w, x, y, z
  object.position.set(pos[0], pos[1], pos[2]);
  object.quaternion.set(quat[1], quat[2], quat[3], quat[0]);
}

function makeView(traj, label, colour) {
  const scene = new THREE.Scene();
  scene.background = new THREE.Color(0xf4f6f8);
  scene.add(new THREE.HemisphereLight(0xffffff, 0x667788, 2.0));
  const sun = new THREE.DirectionalLight(0xffffff, 1.5);
  sun.position.set(3, -4, 6);
  scene.add(sun);
  const regions = traj.terrain?.regions || [], pieces = traj.terrain?.pieces || [];
  if (traj.ground !== false) {
    // The plane z = 0 outside the terrain's regions, large enough to hold them.
    const half = Math.max(10, ...regions.flatMap(r => [...r.min, ...r.max].map(v => Math.abs(v) + 2)));
    const grid = new THREE.GridHelper(2 * half, 4 * half, 0x90a4ae, 0xcfd8dc);
    grid.rotateX(Math.PI / 2);  // z up
    scene.add(grid);
    const outline = new THREE.Shape([[-half, -half], [half, -half], [half, half], [-half, half]].map(([x, y]) => new THREE.Vector2(x, y)));
    for (const r of regions)
      outline.holes.push(new THREE.Path([[r.min[0], r.min[1]], [r.min[0], r.max[1]], [r.max[0], r.max[1]], [r.max[0], r.min[1]]].map(([x, y]) => new THREE.Vector2(x, y))));
    const floor = new THREE.Mesh(new THREE.ShapeGeometry(outline), new THREE.MeshLambertMaterial({ color: 0xe3e8ec }));
    floor.position.z = -0.001;
    scene.add(floor);
  }
  const terrain = new THREE.Group(), props = new THREE.Group();
  for (const p of pieces) {  // green, lighter the higher the top
    const top = p.pos[2] + p.half_extents[2];
    const mesh = new THREE.Mesh(geometry(p), new THREE.MeshLambertMaterial({ color: new THREE.Color().setHSL(0.3, 0.5, Math.min(0.7, Math.max(0.2, 0.4 + 2 * top))) }));
    place(mesh, p.pos, p.quat);
    terrain.add(mesh);
  }
  for (const p of traj.props || []) {
    const mesh = new THREE.Mesh(geometry(p), new THREE.MeshLambertMaterial({ color: 0x8d6e63 }));
    place(mesh, p.pos, p.quat);
    props.add(mesh);
  }
  scene.add(terrain, props);
  const material = new THREE.MeshLambertMaterial({ color: colour });
  const bodies = traj.links.map(link => {
    const group = new THREE.Group();
    for (const g of link.shapes) {
      const mesh = new THREE.Mesh(geometry(g), material);
      place(mesh, g.pos, g.quat);
      group.add(mesh);
    }
    scene.add(group);
    return group;
  });
  const camera = new THREE.PerspectiveCamera(45, width / height, 0.01, 200);
  camera.up.set(0, 0, 1);
  const first = traj.frames[0].links;
  const centre = new THREE.Vector3();
  for (const p of first) centre.add(new THREE.Vector3(p[0], p[1], p[2]));
  centre.divideScalar(Math.max(1, first.length));
  camera.position.set(centre.x + 3, centre.y - 3.5, centre.z + 1.8);
  const renderer = new THREE.WebGLRenderer({ antialias: true, preserveDrawingBuffer: true });
  renderer.setSize(width, height);
  const holder = document.createElement('div');
  holder.className = 'viewport';
  holder.append(renderer.domElement);
  const tag = document.createElement('span');
  tag.className = 'label';
  tag.textContent = label;
  holder.append(tag);
  document.getElementById('viewports').append(holder);
  const controls = new OrbitControls(camera, renderer.domElement);
  controls.target.copy(centre);
  controls.update();
  return {
    traj, duration: traj.frames[traj.frames.length - 1].t, terrain, props,
    show(frame) {
      const poses = traj.frames[frame].links;
      bodies.forEach((b, i) => place(b, poses[i].slice(0, 3), poses[i].slice(3, 7)));
      renderer.render(scene, camera);
    },
    frameAt(t) {  // the last frame at or before t
      let lo = 0, hi = traj.frames.length - 1;
      while (lo < hi) { const mid = (lo + hi + 1) >> 1; if (traj.frames[mid].t <= t) lo = mid; else hi = mid - 1; }
      return lo;
    },
  };
}

async function main() {
  if (!ids.length) throw new Error('no trial given (replay.html?trial=ID[&compare=ID])');
  document.getElementById('crumb-trial').href = `trial.html?id=${encodeURIComponent(ids[0])}`;
  document.getElementById('crumb-trial').textContent = `trial #${ids[0]}`;
  const trajs = await Promise.all(views_asked.map(async ({ id, artifact }) => {
    const r = await fetch(`/api/trials/${encodeURIComponent(id)}/trajectory?artifact=${encodeURIComponent(artifact)}`);
    if (!r.ok) throw new Error(`trial ${id}: ${(await r.json()).error}`);
    // Line 1: the header (links and their shapes); then one frame per line.
    const lines = (await r.text()).split('\n').filter(l => l.trim());
    const traj = JSON.parse(lines[0]);
    if (traj.format !== 'podium-trajectory') throw new Error(`trial ${id}: not a podium trajectory`);
    traj.frames = lines.slice(1).map(l => JSON.parse(l));
    if (!traj.frames.length) throw new Error(`trial ${id}: trajectory has no frames`);
    return traj;
  }));
  const label = v => v.artifact === 'trajectory' ? `trial #${v.id}` : `trial #${v.id} · ${v.artifact.replace(/^trajectory_/, '')}`;
  const views = trajs.map((t, i) => makeView(t, label(views_asked[i]), palette[i]));
  const main = views[0];
  const frames = main.traj.frames.length, duration = Math.max(...views.map(v => v.duration));
  const scrub = document.getElementById('scrub'), counter = document.getElementById('frame');
  const playButton = document.getElementById('play'), speed = document.getElementById('speed');
  scrub.max = frames - 1;
  let playing = true, t = 0, last = performance.now();
  window.podiumReplay = {
    frame: 0, frames, rendered: 0,
    drawn: { props: main.props.children.length, terrain: main.terrain.children.length },
  };
  const draw = () => {
    for (const v of views) v.show(v.frameAt(Math.min(t, v.duration)));
    const f = main.frameAt(Math.min(t, main.duration));
    scrub.value = f;
    counter.textContent = `frame ${f + 1} / ${frames} · t = ${t.toFixed(2)} s`;
    window.podiumReplay.frame = f;
    window.podiumReplay.rendered++;
  };
  for (const part of ['props', 'terrain']) {
    const box = document.getElementById(`show-${part}`);
    box.onchange = () => { for (const v of views) v[part].visible = box.checked; draw(); };
  }
  playButton.onclick = () => { playing = !playing; playButton.textContent = playing ? 'pause' : 'play'; };
  scrub.oninput = () => { playing = false; playButton.textContent = 'play'; t = main.traj.frames[+scrub.value].t; draw(); };
  const loop = now => {
    if (playing) {
      t += (now - last) / 1000 * +speed.value;
      if (t > duration) t = 0;
      draw();
    }
    last = now;
    requestAnimationFrame(loop);
  };
  draw();
  requestAnimationFrame(loop);
}

main().catch(e => { document.getElementById('error').textContent = e.message; });
