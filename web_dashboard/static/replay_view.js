// One 3D view of a recorded motion (sim/'s trajectory file, JSON lines; format in
// web_dashboard/README.md): bodies as capsules, boxes and spheres, the ground (with holes where
// terrain regions replace it), the terrain's boxes and the props (bar, box, blocks), an orbiting
// camera. Shared by the replay page and the campaign page's strategy gallery.
import * as THREE from './vendor/three.module.js';
import { OrbitControls } from './vendor/OrbitControls.js';

/// The trajectory artifact `artifact` of trial `id`: the header with its frames.
export async function loadTrajectory(id, artifact = 'trajectory') {
  const r = await fetch(`/api/trials/${encodeURIComponent(id)}/trajectory?artifact=${encodeURIComponent(artifact)}`);
  if (!r.ok) throw new Error(`trial ${id}: ${(await r.json()).error}`);
  // Line 1: the header (links and their shapes); then one frame per line.
  const lines = (await r.text()).split('\n').filter(l => l.trim());
  const traj = JSON.parse(lines[0]);
  if (traj.format !== 'podium-trajectory') throw new Error(`trial ${id}: not a podium trajectory`);
  traj.frames = lines.slice(1).map(l => JSON.parse(l));
  if (!traj.frames.length) throw new Error(`trial ${id}: trajectory has no frames`);
  return traj;
}

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

export function makeView(traj, { label, colour, width, height, parent }) {
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
  parent.append(holder);
  const controls = new OrbitControls(camera, renderer.domElement);
  controls.target.copy(centre);
  controls.update();
  // Times count from the motion's first frame: a recording that begins after a fall (a get-up's
  // fast run starts at t = 2 s, its slowed runs at 0) plays beside another from the same moment.
  const t0 = traj.frames[0].t;
  return {
    traj, duration: traj.frames[traj.frames.length - 1].t - t0, terrain, props,
    timeOf(frame) { return traj.frames[frame].t - t0; },
    show(frame) {
      const poses = traj.frames[frame].links;
      bodies.forEach((b, i) => place(b, poses[i].slice(0, 3), poses[i].slice(3, 7)));
      renderer.render(scene, camera);
    },
    frameAt(t) {  // the last frame at or before t (from the first frame)
      let lo = 0, hi = traj.frames.length - 1;
      while (lo < hi) { const mid = (lo + hi + 1) >> 1; if (traj.frames[mid].t - t0 <= t) lo = mid; else hi = mid - 1; }
      return lo;
    },
  };
}
