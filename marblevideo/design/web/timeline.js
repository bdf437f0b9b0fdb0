// Time: the slider, the clock, play and loop. In live mode the clock is the
// live session's (GET /stats, POST /control) and the sheet shows its frames.
import * as api from "./api.js";
import { $ } from "./dom.js";
import { isRendering, show } from "./sheet.js";
import { get, update, isLive } from "./store.js";

export function setTime(value) {
  update((s) => ({t: Math.max(0, Math.min(s.duration, value))}));
}
let last = null;
// Play's clock: the next frame's time (the sheet view renders it), then the next tick once it is shown.
export function tick(now) {
  const s = get();
  if (isRendering()) return;
  if (isLive(s)) { show(); return; }  // the clock is the session's: its newest frame (a stroke being drawn too)
  if (s.gesture) return;
  if (!s.playing) { if (s.info.input.kind === "live") show({draft: true}); return; }
  const dt = last === null ? 0 : (now - last) / 1000;
  last = now;
  const next = s.t + dt;
  if (next > s.duration && !s.loop) update(() => ({t: s.duration, playing: false}));
  else if (next > s.duration) update(() => ({t: 0}));
  else if (next !== s.t) update(() => ({t: next}));
  else show({draft: true});
}
// The next tick, while playing or while a live source moves the sheet (not
// during a gesture, but in live mode: the live frames show the stroke drawn).
export function resume() {
  const s = get();
  if (isLive(s) || s.playing || (s.info.input.kind === "live" && !s.gesture)) requestAnimationFrame(tick);
}
export function togglePlay() {
  if (isLive()) { control({paused: get().playing}); return; }
  last = null;
  update((s) => ({playing: !s.playing}));
}
// Live mode: the session's counters and clock, as /stats has them (an answer
// older than one shown already, a poll's overtaken by a control's, is dropped).
let statsAsked = 0, statsShown = 0;
export async function liveStats() {
  const n = ++statsAsked;
  const s = await api.stats();
  if (n < statsShown) return;
  statsShown = n;
  update(() => ({live: s, playing: !s.paused, loop: s.loop !== null}));
  if (document.activeElement !== $("time")) setTime(s.t);  // not while the hand is on the slider
}
async function control(request) {
  const r = await api.control(request);
  const answer = await r.json();
  if (!r.ok) update(() => ({error: answer.error}));
  else await liveStats();
}

// The time slider and the clock (live mode: the session's time, set only while
// the hand is not on the slider, see liveStats). Past the recipe's end (live, loop
// off: the session's clock runs on) the slider rests at the end and the clock
// says so, with the session's time.
export const clockOf = (s) => [s.t, s.duration, isLive(s) && s.live ? s.live.t : null];
export function showClock(s) {
  const session = isLive(s) && s.live ? s.live.t : null, past = session !== null && session > s.duration;
  $("time").max = s.duration;
  $("time").value = s.t;
  $("clock").textContent = past ? `t = ${session.toFixed(2)} s, past the recipe's end (${s.duration.toFixed(2)} s)`
    : `t = ${s.t.toFixed(2)} s`;
  $("clock").classList.toggle("past", past);
}
// Play, loop, and live mode's counters and switches.
export const playOf = (s) => [s.playing, s.loop, s.live];
export function showPlay(s) {
  $("play").textContent = s.playing ? "Pause" : "Play";
  $("loop").checked = s.loop;
  if (!s.live) return;
  $("fps").textContent = s.live.fps.toFixed(1);
  $("latency").textContent = s.live.latency_ms === null ? "-" : s.live.latency_ms.toFixed(0);
  $("frames").textContent = s.live.frames;
  $("dropped").textContent = s.live.dropped;
  $("bypass").checked = s.live.bypass;
  $("mirror").checked = s.live.mirror;
}
export function initTimeline() {
  $("time").addEventListener("input", () => {
    if (isLive()) control({time: Number($("time").value)});
    else setTime(Number($("time").value));
  });
  $("loop").addEventListener("change", () => {
    if (isLive()) control({loop: $("loop").checked});
    else update(() => ({loop: $("loop").checked}));
  });
  for (const name of ["bypass", "mirror"]) $(name).addEventListener("change", () => control({[name]: $(name).checked}));
}
