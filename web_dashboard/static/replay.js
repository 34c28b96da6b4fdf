// 3D replay of recorded motion (sim/'s trajectory file, JSON lines; format in web_dashboard/README.md):
// bodies as capsules, boxes and spheres, the ground (with holes where terrain regions replace it),
// the terrain's boxes (tiles, flat patches, slopes) and the props (bar, box, blocks); play, pause,
// scrub, speed, camera orbit, props and terrain shown or hidden; with ?compare=ID a second trial
// side by side on the same clock. A trial may be written ID:NAME to show its trajectory artifact
// NAME (e.g. 12:trajectory_fast beside 12:trajectory, a get-up fast and slowed). When the first
// trial's `curves` artifact holds the episode of the motion shown (a style-curve get-up), its
// target and achieved features are plotted beside the view, a line marking the replay's time.
import { loadTrajectory, makeView } from './replay_view.js';

const params = new URLSearchParams(location.search);
const views_asked = [params.get('trial'), params.get('compare')].filter(Boolean).map(v => {
  const at = v.indexOf(':');
  return at < 0 ? { id: v, artifact: 'trajectory' } : { id: v.slice(0, at), artifact: v.slice(at + 1) };
});
const ids = views_asked.map(v => v.id);
const palette = [0x4e79a7, 0xf28e2b];
const height = 520;

async function main() {
  if (!ids.length) throw new Error('no trial given (replay.html?trial=ID[&compare=ID])');
  // Each view is labelled with its trial's name and what its motion is (a get-up's κ).
  const trials = await Promise.all(views_asked.map(({ id }) => podium.api(`/api/trials/${encodeURIComponent(id)}`)));
  const first = trials[0];
  document.title = `Podium · replay ${first.name}`;
  const crumbCampaign = document.getElementById('crumb-campaign');
  crumbCampaign.href = `campaign.html?id=${first.campaign_id}`;
  crumbCampaign.textContent = first.campaign_name;
  document.getElementById('crumb-trial').href = `trial.html?id=${encodeURIComponent(ids[0])}`;
  document.getElementById('crumb-trial').textContent = first.name;
  const trajs = await Promise.all(views_asked.map(({ id, artifact }) => loadTrajectory(id, artifact)));
  const labels = views_asked.map((v, i) => podium.motionLabel(trials[i], v.artifact));
  const parent = document.getElementById('viewports');
  // Narrower beside a style-curve get-up's plots (styleCurvesBeside).
  const width = ids.length > 1 ? 560 : first.artifacts.some(a => a.name === 'curves') ? 720 : 900;
  const views = trajs.map((t, i) => makeView(t, { label: labels[i], colour: palette[i], width, height, parent }));
  const main = views[0];
  const frames = main.traj.frames.length, duration = Math.max(...views.map(v => v.duration));
  const scrub = document.getElementById('scrub'), counter = document.getElementById('frame');
  const playButton = document.getElementById('play'), speed = document.getElementById('speed');
  scrub.max = frames - 1;
  let playing = true, t = 0, last = performance.now();
  const curves = await styleCurvesBeside(first, views_asked[0].artifact, parent, () => t);
  last = performance.now();
  // For the browser tests: the first view's frames and simulated seconds, and what it draws
  // (kinds: each prop's, as the file declares it).
  window.podiumReplay = {
    frame: 0, frames, rendered: 0, shown: [], labels,  // shown: each view's frame
    duration: main.duration,
    drawn: { props: main.props.children.length, terrain: main.terrain.children.length },
    kinds: main.props.children.map(c => c.userData.kind),
    root_x: [main.traj.frames[0].links[0][0], main.traj.frames[frames - 1].links[0][0]],  // the first link's x, first and last frame
    camera_x: 0,
  };
  const draw = () => {
    window.podiumReplay.shown = views.map(v => v.frameAt(Math.min(t, v.duration)));
    views.forEach((v, i) => v.show(window.podiumReplay.shown[i]));
    window.podiumReplay.camera_x = main.cameraX();
    const f = window.podiumReplay.shown[0];
    scrub.value = f;
    counter.textContent = `frame ${f + 1} / ${frames} · t = ${t.toFixed(2)} s`;
    if (curves && f !== window.podiumReplay.frame) curves.redraw();
    window.podiumReplay.frame = f;
    window.podiumReplay.rendered++;
  };
  for (const part of ['props', 'terrain']) {
    const box = document.getElementById(`show-${part}`);
    box.onchange = () => { for (const v of views) v[part].visible = box.checked; draw(); };
  }
  playButton.onclick = () => { playing = !playing; playButton.textContent = playing ? 'pause' : 'play'; };
  scrub.oninput = () => { playing = false; playButton.textContent = 'play'; t = main.timeOf(+scrub.value); draw(); };
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

// The style-curve panels of the motion `artifact` of trial `t`, in a column beside the views, or
// null when its trial has no `curves` artifact or none of its episodes is that motion.
async function styleCurvesBeside(t, artifact, parent, time) {
  if (!t.artifacts.some(a => a.name === 'curves')) return null;
  const doc = await podium.api(`/api/trials/${encodeURIComponent(t.id)}/curves`);
  const k = doc.episodes.findIndex(e => e.trajectory === artifact);
  if (k < 0) return null;
  const column = podium.el('div', { class: 'style-curves-column', id: 'style-curves' });
  parent.append(column);
  const panels = podium.styleCurvePanels(column, doc, { only: [k], marker: time, width: 340, height: 160 });
  column.append(podium.el('div', { class: 'muted caption' }, 'target dashed, achieved solid · ' + podium.styleCurveCaption(doc, [k])));
  return panels;
}

main().catch(e => { document.getElementById('error').textContent = e.message; });
