// The designer's HTTP API (marblevideo.design), as the page uses it.
const JSON_HEADERS = {"Content-Type": "application/json"};

export const getJSON = async (path) => (await fetch(path)).json();
export const ops = () => getJSON("/api/ops");
export const info = () => getJSON("/api/info");
export const stats = () => getJSON("/stats");
export const signals = () => getJSON("/api/signals");
// Live mode's motion of the last frame (``shapes``: its regions and strokes too).
export const motion = (shapes = true) => getJSON(`/api/motion${shapes ? "" : "?shapes=0"}`);
export const recipe = () => fetch("/api/recipe");  // 409 while FILE on disk is broken
export const putRecipe = (doc) => fetch("/api/recipe", {method: "PUT", headers: JSON_HEADERS, body: JSON.stringify(doc)});
export const post = (path, obj) => fetch(path, {method: "POST", headers: JSON_HEADERS, body: JSON.stringify(obj)});
// The frame of a recipe not saved, as raw RGBA (frame.rgba): nothing to encode or decode.
export const frameOf = (query, doc) => post(`/api/frame.rgba?${query}`, doc);
// Live mode: the newest marbled frame newer than seq (204 No Content after 2 s without one).
export const liveFrame = (seq) => fetch(`/frame.jpg?after=${seq}`);
export const control = (request) => post("/control", request);
// Live mode: {recipe, version}: an unsaved recipe the live frames show until a save (recipe null: none).
export const putPreview = (body) => fetch("/api/preview", {method: "PUT", headers: JSON_HEADERS, body: JSON.stringify(body)});
export const learn = () => post("/api/learn", {});
