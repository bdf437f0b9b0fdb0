// A keyframe track as a parameter's field shows it, a short list, and back:
// "0 s: 10 (ease-in-out) → 1.5 s: 18", each key's time, value and, in brackets,
// the ease that leaves it (a name, or cubic-bezier points "0, 0.9, 0, 1"), as in
// marblevideo.recipe.keyframes. A field takes such a list (-> for →), JSON, or a
// plain value (a colour's name or #rrggbb too).
const ARROW = " → ";
const spell = (v) => (Array.isArray(v) ? `[${v.map(spell).join(", ")}]` : String(v));
const easeText = (e) => (Array.isArray(e) ? e.join(", ") : e);
// A value the list can carry and read back: a number, a word or #hex, or a list of them.
const plain = (v) => (Array.isArray(v) ? v.every(plain) : typeof v === "number" || /^#?[\w-]+$/.test(v));
const plainKey = (k) => Object.keys(k).every((f) => ["t", "v", "ease"].includes(f))
  && typeof k.t === "number" && plain(k.v)
  && (k.ease === undefined || (Array.isArray(k.ease) ? k.ease.every((x) => typeof x === "number") : /^[\w-]+$/.test(k.ease)));

// A track's list; null where the list cannot say it (fields besides keys, or a key's besides t, v, ease).
export function keysText(track) {
  const {keys, ...rest} = track;
  if (Object.keys(rest).length || !Array.isArray(keys) || !keys.length || !keys.every(plainKey)) return null;
  return keys.map((k) => `${k.t} s: ${spell(k.v)}${k.ease === undefined ? "" : ` (${easeText(k.ease)})`}`).join(ARROW);
}

function valueOf(text) {
  try { return JSON.parse(text); } catch (e) { /* a word: a colour */ }
  if (/^#?[\w-]+$/.test(text)) return text;
  throw new Error(`'${text}' is not a value`);
}
function easeOf(text) {
  if (/^[a-z-]+$/.test(text)) return text;
  const points = text.split(",").map(Number);
  if (points.length !== 4 || !points.every(Number.isFinite)) throw new Error(`'${text}' is not an ease`);
  return points;
}
const KEY = /^([-+]?[0-9.]+(?:e[-+]?[0-9]+)?)\s*s\s*:\s*(.+?)\s*(?:\(([^()]*)\))?$/i;
function parseKeys(text) {
  return {keys: text.split(/→|->/).map((part, n) => {
    const m = KEY.exec(part.trim());
    if (!m || !Number.isFinite(Number(m[1]))) {
      throw new Error(`key ${n + 1} '${part.trim()}': expected "TIME s: VALUE" or "TIME s: VALUE (EASE)"`);
    }
    const key = {t: Number(m[1]), v: valueOf(m[2])};
    if (m[3] !== undefined) key.ease = easeOf(m[3].trim());
    return key;
  })};
}
// What a text field holds: undefined if nothing, JSON as it is, else keys or a plain value.
export function parseField(text) {
  const s = text.trim();
  if (s === "") return undefined;
  try { return JSON.parse(s); } catch (e) { /* keys, or a word */ }
  if (/→|->|^[-+0-9.e]+\s*s\s*:/i.test(s)) return parseKeys(s);
  return valueOf(s);
}
