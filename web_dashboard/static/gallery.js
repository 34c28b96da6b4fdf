// The campaign page's strategy gallery: each distinct strategy as a moving 3D replay of its
// representative trial (the `trajectory` artifact), side by side, with its features, objective and
// the task's own summary of the trial (RunResult::info's `summary` object, e.g. the bar height a
// jumper reached and its nearest captured technique). campaign.js announces the strategy table
// with a `podium-strategies` event on every refresh (and keeps it in window.podiumStrategies); a card is built once per representative
// trial and kept while it stays one. window.podiumGallery counts cards and frames drawn and lists
// each card's props by kind (the browser tests read it).
import { loadTrajectory, makeView } from './replay_view.js';

const MAX_CARDS = 12;  // a browser keeps about 16 WebGL contexts alive
const gallery = document.getElementById('gallery');
const cards = new Map();  // representative trial id → { element, view }
// Only cards on screen are drawn: a dozen views drawn off screen would keep a software-rendered
// (headless, or GPU-less) page busy for nothing.
const onScreen = new Set();
const watcher = new IntersectionObserver(entries => {
  for (const e of entries) if (e.isIntersecting) onScreen.add(e.target); else onScreen.delete(e.target);
});
window.podiumGallery = { cards: 0, rendered: 0, kinds: {} };  // kinds: per card's trial, its props' kinds

function text(tag, content, cls) {
  const e = document.createElement(tag);
  if (cls) e.className = cls;
  e.textContent = content;
  return e;
}

const num = v => (typeof v === 'number' ? (Math.abs(v) >= 100 ? v.toFixed(0) : v.toPrecision(3)) : String(v));

async function makeCard(s, stageName, featureNames) {
  const element = document.createElement('div');
  element.className = 'card';
  element.dataset.trial = s.representative_trial;
  const title = document.createElement('div');
  const link = text('a', `${stageName} · strategy ${s.label}`);
  link.href = `replay.html?trial=${encodeURIComponent(s.representative_trial)}`;
  title.append(link, text('span', ` · trial ${s.representative_name} · ${s.trials} trial${s.trials === 1 ? '' : 's'}`, 'muted'));
  const facts = document.createElement('div');
  facts.className = 'facts';
  facts.append(text('div', s.features.map((f, k) => `${featureNames[k] || 'f' + k} = ${num(f)}`).join(' · ')));
  if (s.best_objective !== null && s.best_objective !== undefined) facts.append(text('div', `objective ${num(s.best_objective)}`));
  const holder = document.createElement('div');
  element.append(title, holder, facts);
  gallery.append(element);
  watcher.observe(element);
  const trial = await podium.api(`/api/trials/${encodeURIComponent(s.representative_trial)}`);
  for (const [key, value] of Object.entries(trial.result_info?.summary || {})) facts.append(text('div', `${key}: ${num(value)}`));
  const traj = (trial.artifacts || []).some(a => a.name === 'trajectory') ? await loadTrajectory(s.representative_trial) : null;
  if (!traj) {
    holder.append(text('div', 'no motion recorded', 'muted'));
    return { element, view: null };
  }
  const view = makeView(traj, { label: '', colour: podium.colour(s.label), width: 300, height: 240, parent: holder });
  window.podiumGallery.kinds[s.representative_trial] = view.props.children.map(c => c.userData.kind);
  return { element, view };
}

// At most 15 frames a second, on-screen cards only.
const clockStart = performance.now();
let lastDrawn = -Infinity;
function animate(now) {
  requestAnimationFrame(animate);
  if (now - lastDrawn < 66) return;
  lastDrawn = now;
  const t = (now - clockStart) / 1000;
  for (const { element, view } of cards.values()) {
    if (!view || !onScreen.has(element)) continue;
    view.show(view.frameAt(t % Math.max(view.duration, 1e-6)));
    window.podiumGallery.rendered++;
  }
}

async function render({ list, stages }) {
  // Only strategies whose representative recorded a motion (a landscape's have none).
  const shown = list.filter(s => s.representative_trial !== null && s.representative_trial !== undefined && s.motion !== false)
    .slice(0, MAX_CARDS);
  document.getElementById('no-gallery').hidden = shown.length > 0;
  const keep = new Set(shown.map(s => String(s.representative_trial)));
  for (const [id, card] of cards)
    if (!keep.has(id) && card.element) {
      watcher.unobserve(card.element);
      onScreen.delete(card.element);
      card.element.remove();
      cards.delete(id);
    }
  for (const s of shown) {
    const id = String(s.representative_trial);
    if (cards.has(id)) continue;
    cards.set(id, { element: null, view: null });  // claimed: a refresh during the fetch skips it
    const stage = stages[s.stage];
    const names = (stage?.description?.features || []).map(f => f.name);
    cards.set(id, await makeCard(s, stage?.name ?? s.stage, names));
  }
  window.podiumGallery.cards = [...cards.values()].filter(c => c.view).length;
}

// campaign.js may have announced the table before this module ran.
if (window.podiumStrategies) render(window.podiumStrategies);
document.addEventListener('podium-strategies', ev => render(ev.detail));
requestAnimationFrame(animate);
