// A number's slider range: its parameter's law as /api/ops describes it
// (marblevideo.ops.base.SLIDER_SPECS, which Python's slider_range evaluates the
// same way): [min, max, step] for a value v on a canvas whose larger side is size.
export function sliderRange(param, v, size) {
  const s = param.range;
  let term = s.times * (s.absolute ? Math.abs(v) : v);
  if (s.ceil) term = Math.ceil(term);
  let least = s.least;
  for (let k = 0; k < s.power; k++) least *= size;
  const hi = Math.max(term, least / s.per);
  const lo = {mirror: -hi, zero: 0, thousandth: hi / 1000}[s.lo];
  return [lo, hi, s.step || hi / s.steps];
}
