// Plain values: rounding, copies, and what a recipe's value is (keys, a signal).
export const round1 = (v) => Math.round(v * 10) / 10;
export const round3 = (v) => Math.round(v * 1000) / 1000;
export const clone = (v) => JSON.parse(JSON.stringify(v));
export function isTrack(v) { return v !== null && typeof v === "object" && !Array.isArray(v) && "keys" in v; }
export function isSignal(v) { return v !== null && typeof v === "object" && !Array.isArray(v) && "signal" in v; }
