// One 3D view of a recorded motion (sim/'s trajectory file, JSON lines; format in
// web_dashboard/README.md): bodies as capsules, boxes and spheres, the ground (with holes where
// terrain regions replace it), the terrain's boxes and the props as their `kind` says (a crossbar on
// two standards, a landing mat, an obstacle box, a plain box, a line painted on the ground), an
// orbiting camera that frames a jump's whole motion or, on a track (lines), runs beside the runner. Shared by the replay page and the campaign page's strategy gallery.
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

const lambert = color => new THREE.MeshLambertMaterial({ color });
const PROP_COLOURS = { box: 0x8d6e63, obstacle: 0xc7782e, mat: 0x1e5fae, line: 0x263238 };
// A high-jump bar and its standards (World Athletics: the bar 3.98–4.02 m long, 30 mm round).
const BAR_LENGTH = 4.0, BAR_RADIUS = 0.015, BAR_BANDS = 8, STANDARD_RADIUS = 0.025, STANDARD_ABOVE = 0.35;

// A point of the motion in the prop's frame (p's pos and quat).
function toLocal(p, point) {
  const q = new THREE.Quaternion(p.quat[1], p.quat[2], p.quat[3], p.quat[0]).invert();
  return new THREE.Vector3(point[0] - p.pos[0], point[1] - p.pos[1], point[2] - p.pos[2]).applyQuaternion(q);
}

// Kind "crossbar": the box is the bar's collision stand-in (a wall from the ground up to the bar,
// along its local y); drawn is the bar at the box's top edge, centred where the centre of mass
// passes the box's mid-plane (a jumper takes the bar's middle), on two standards from the ground.
function crossbar(p, frames) {
  const [, hy, hz] = p.half_extents;
  const nearest = frames.map(f => toLocal(p, f.com)).reduce((a, b) => (Math.abs(b.x) < Math.abs(a.x) ? b : a));
  const room = Math.max(0, hy - BAR_LENGTH / 2);
  const centre = Math.min(room, Math.max(-room, nearest.y));
  const group = new THREE.Group();
  const band = Math.min(BAR_LENGTH, 2 * hy) / BAR_BANDS;
  for (let k = 0; k < BAR_BANDS; ++k) {  // three's cylinders run along y, as the bar does
    const piece = new THREE.Mesh(new THREE.CylinderGeometry(BAR_RADIUS, BAR_RADIUS, band, 12), lambert(k % 2 ? 0xf5f5f5 : 0xd32f2f));
    piece.position.set(0, centre + (k + 0.5 - BAR_BANDS / 2) * band, hz - BAR_RADIUS);
    group.add(piece);
  }
  const height = 2 * hz + STANDARD_ABOVE;
  for (const side of [-1, 1]) {
    const y = centre + side * (BAR_BANDS * band / 2 + 2 * STANDARD_RADIUS);
    const post = new THREE.Mesh(new THREE.CylinderGeometry(STANDARD_RADIUS, STANDARD_RADIUS, height, 12), lambert(0x455a64));
    post.rotateX(Math.PI / 2);
    post.position.set(0, y, height / 2 - hz);
    const foot = new THREE.Mesh(new THREE.BoxGeometry(0.35, 0.35, 0.02), lambert(0x455a64));
    foot.position.set(0, y, 0.01 - hz);
    const peg = new THREE.Mesh(new THREE.BoxGeometry(0.04, 0.06, 0.02), lambert(0x263238));
    peg.position.set(0, y - side * 2 * STANDARD_RADIUS, hz - 2 * BAR_RADIUS - 0.01);
    group.add(post, foot, peg);
  }
  return group;
}

// The 3D object of one prop, tagged with its kind (userData.kind; a file without kinds: boxes).
function propObject(p, frames) {
  const kind = p.kind || 'box';
  const material = lambert(PROP_COLOURS[kind] ?? PROP_COLOURS.box);
  // A mat a few centimetres thick and a painted line a millimetre above the ground: drawn ahead of
  // the floor's grid lines at equal depth.
  if (kind === 'mat' || kind === 'line')
    Object.assign(material, { polygonOffset: true, polygonOffsetFactor: -2, polygonOffsetUnits: -4 });
  const object = kind === 'crossbar' ? crossbar(p, frames) : new THREE.Mesh(geometry(p), material);
  place(object, p.pos, p.quat);
  object.userData = { kind, name: p.name };
  object.name = p.name || kind;
  return object;
}

// The camera for a jump (a crossbar or an obstacle in the scene): the whole motion in view, seen
// from the take-off side at 45° to the bar (looking along the bar would hide it, across it the
// arc), on the side that shows the jumper's travel across the picture, a little from above (the height over the bar reads best low).
function frameJump(camera, p, frames) {
  const box = new THREE.Box3();
  for (const f of frames) for (const l of f.links) box.expandByPoint(new THREE.Vector3(l[0], l[1], l[2]));
  const target = box.getCenter(new THREE.Vector3()), size = box.getSize(new THREE.Vector3());
  const q = new THREE.Quaternion(p.quat[1], p.quat[2], p.quat[3], p.quat[0]);
  const over = new THREE.Vector3(1, 0, 0).applyQuaternion(q), along = new THREE.Vector3(0, 1, 0).applyQuaternion(q);
  const first = frames[0].com, last = frames[frames.length - 1].com;
  const travel = new THREE.Vector3(last[0] - first[0], last[1] - first[1], 0).normalize();
  const sides = [1, -1].map(s => over.clone().negate().add(along.clone().multiplyScalar(s)).normalize());
  const side = sides.reduce((a, b) => (Math.abs(b.x * travel.y - b.y * travel.x) > Math.abs(a.x * travel.y - a.y * travel.x) ? b : a));
  // Far enough for the motion's ground extent across the picture and its height up it, with a margin.
  const half = Math.tan(THREE.MathUtils.degToRad(camera.fov / 2));
  const distance = 1.1 * Math.max(0.5 * Math.hypot(size.x, size.y) / (half * camera.aspect), 0.5 * size.z / half, 2.5) + 0.3 * Math.hypot(size.x, size.y);
  camera.position.copy(target).addScaledVector(side.setZ(0.15).normalize(), distance);
  // Metres away, a near plane of 1 cm leaves a thin mat's top and the floor to fight over depth.
  camera.near = 0.1;
  camera.updateProjectionMatrix();
  return target;
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
    // The plane z = 0 outside the terrain's regions, large enough to hold them and the props (a
    // track's lines run past its finish).
    const reach = (traj.props || []).flatMap(p => [0, 1].map(i => Math.abs(p.pos[i]) + Math.max(...p.half_extents) + 2));
    const half = Math.ceil(Math.max(10, ...reach, ...regions.flatMap(r => [...r.min, ...r.max].map(v => Math.abs(v) + 2))));
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
  for (const p of traj.props || []) props.add(propObject(p, traj.frames));
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
  const jump = (traj.props || []).find(p => p.kind === 'crossbar' || p.kind === 'obstacle');
  const track = !jump && (traj.props || []).some(p => p.kind === 'line');
  let centre = new THREE.Vector3();
  if (jump) {
    centre = frameJump(camera, jump, traj.frames);
  } else {  // beside the first frame's centre (a get-up, a swing)
    const first = traj.frames[0].links;
    for (const p of first) centre.add(new THREE.Vector3(p[0], p[1], p[2]));
    centre.divideScalar(Math.max(1, first.length));
    camera.position.set(centre.x + 3, centre.y - 3.5, centre.z + 1.8);
    if (track) camera.position.set(centre.x + 1.5, centre.y - 6, centre.z + 1.2);  // beside the lane
  }
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
    cameraX: () => camera.position.x,
    timeOf(frame) { return traj.frames[frame].t - t0; },
    show(frame) {
      const poses = traj.frames[frame].links;
      bodies.forEach((b, i) => place(b, poses[i].slice(0, 3), poses[i].slice(3, 7)));
      if (track) {  // the camera runs beside the runner: it and its target move with the root along the track
        const dx = poses[0][0] - controls.target.x;
        camera.position.x += dx;
        controls.target.x += dx;
        controls.update();
      }
      renderer.render(scene, camera);
    },
    frameAt(t) {  // the last frame at or before t (from the first frame)
      let lo = 0, hi = traj.frames.length - 1;
      while (lo < hi) { const mid = (lo + hi + 1) >> 1; if (traj.frames[mid].t - t0 <= t) lo = mid; else hi = mid - 1; }
      return lo;
    },
  };
}
