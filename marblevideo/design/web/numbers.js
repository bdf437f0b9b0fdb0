// A number parameter as the page shows it: its value at the time shown (as the
// renderer evaluates its track) and its slider's range on this canvas.
import { valueAt } from "./ease.js";
import { sliderRange } from "./range.js";
import { get } from "./store.js";

export const valueNow = (v, tt = get().t) => valueAt(v, tt);
// The canvas's larger side: what slider ranges scale with.
const size = () => Math.max(get().info.canvas[0], get().info.canvas[1]);
export const rangeOf = (p, v) => sliderRange(p, v, size());
