// Time: the slider, the clock, play and loop. In live mode the clock is the
// live session's (GET /stats, POST /control) and the sheet shows its frames.
import * as api from "./api.js";
import { isRendering, show } from "./sheet.js";
import { $, state, isLive, showError } from "./state.js";

export function setDuration() {
  const end = Math.max(state.info.end || 0, state.info.input.duration || 0, 1);
  $("time").max = end;
  if (state.t > end) setTime(end, false);
}
export function setTime(value, render = true) {
  const t = state.t = Math.max(0, Math.min(Number($("time").max), value));
  $("time").value = t;
  $("clock").textContent = `t = ${t.toFixed(2)} s`;
  $("export-png").href = isLive() ? "/frame.jpg" : `/api/frame.png?t=${t.toFixed(3)}`;
  $("export-svg").href = `/api/design.svg?t=${t.toFixed(3)}`;
  if (render) show({draft: state.playing});
}
let last = null;
export function tick(now) {
  if (isRendering() || state.gesture) return;
  if (isLive()) { show(); return; }  // the clock is the session's: show its newest frame
  if (!state.playing) { if (state.info.input.kind === "live") show({draft: true}); return; }
  const dt = last === null ? 0 : (now - last) / 1000;
  last = now;
  let next = state.t + dt;
  const end = Number($("time").max);
  if (next > end) {
    if ($("loop").checked) next = 0;
    else { next = end; state.playing = false; $("play").textContent = "Play"; }
  }
  setTime(next, false);
  show({draft: state.playing});
}
// Live mode: the session's counters and clock, as /stats has them (an answer
// older than one shown already, a poll's overtaken by a control's, is dropped).
let statsAsked = 0, statsShown = 0;
export async function liveStats() {
  const n = ++statsAsked;
  const s = await api.stats();
  if (n < statsShown) return;
  statsShown = n;
  $("fps").textContent = s.fps.toFixed(1);
  $("latency").textContent = s.latency_ms === null ? "-" : s.latency_ms.toFixed(0);
  $("frames").textContent = s.frames;
  $("dropped").textContent = s.dropped;
  state.playing = !s.paused;
  $("play").textContent = state.playing ? "Pause" : "Play";
  $("loop").checked = s.loop !== null;
  $("bypass").checked = s.bypass;
  $("mirror").checked = s.mirror;
  if (document.activeElement !== $("time")) setTime(s.t, false);
}
async function control(request) {
  const r = await api.control(request);
  const answer = await r.json();
  if (!r.ok) showError(answer.error);
  else await liveStats();
}
export function initTimeline() {
  $("play").addEventListener("click", () => {
    if (isLive()) { control({paused: state.playing}); return; }
    state.playing = !state.playing;
    last = null;
    $("play").textContent = state.playing ? "Pause" : "Play";
    if (state.playing) requestAnimationFrame(tick); else show();
  });
  $("time").addEventListener("input", () => {
    if (isLive()) control({time: Number($("time").value)});
    else setTime(Number($("time").value));
  });
  $("loop").addEventListener("change", () => { if (isLive()) control({loop: $("loop").checked}); });
  for (const name of ["bypass", "mirror"]) $(name).addEventListener("change", () => control({[name]: $(name).checked}));
}
