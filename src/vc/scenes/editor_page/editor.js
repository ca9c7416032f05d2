// vc-scene edit: the scene's layout, zones and measured ground points drawn over its background, in its pixels.
// The server (vc/scenes/editor_server.py) projects everything through the camera; this page only draws and edits
// pixels, and posts the edit back: "Check" plans the regions without writing, "Save" writes scene.yaml if the
// scene's own loader accepts it, and shows the loader's message if not.
"use strict";

const SVG = "http://www.w3.org/2000/svg";
const KINDS = ["walkable", "obstacles", "walls", "zones", "points"];
const DEFAULTS = {
  cylinder: { radius: 0.3, height: 1.0 },
  box: { height: 1.0, bottom: 0 },
  wall: { height: 2.5, thickness: 0.2 },
};
const REGION_COLOURS = ["#e6194b", "#3cb44b", "#0082c8", "#f58230", "#911eb4", "#46f0f0", "#f032e6", "#d2f53c"];
const FIGURE_DELAY_MS = 60;

const page = {
  state: null, // the server's page state
  elements: { walkable: [], obstacles: [], walls: [], zones: [], points: [] },
  removed: { walkable: [], obstacles: [], walls: [], zones: [], points: [] },
  tool: "select",
  draft: [],
  selected: null, // {kind, index}
  drag: null, // {kind, index, point}
  figureTimer: null,
};

const $ = (id) => document.getElementById(id);

function svgElement(name, attributes, parent) {
  const element = document.createElementNS(SVG, name);
  for (const [key, value] of Object.entries(attributes || {})) element.setAttribute(key, value);
  if (parent) parent.appendChild(element);
  return element;
}

function pointsAttribute(points) {
  return points.map(([u, v]) => `${u},${v}`).join(" ");
}

function say(text, kind) {
  const message = $("message");
  message.textContent = text;
  message.className = kind || "";
}

async function request(method, url, body) {
  const options = { method, headers: {} };
  if (body !== undefined) {
    options.body = JSON.stringify(body);
    options.headers["Content-Type"] = "application/json";
  }
  const response = await fetch(url, options);
  const data = await response.json();
  if (!response.ok) throw new Error(data.error || `${response.status}`);
  return data;
}

// ------------------------------------------------------------------------------------------------ the scene's state

function adopt(state) {
  page.state = state;
  for (const kind of KINDS) {
    page.elements[kind] = state[kind].map((element) => ({ ...element, edited: false }));
    page.removed[kind] = [];
  }
  page.selected = null;
  page.draft = [];
  $("scene-name").textContent = state.scene;
  $("frame-note").textContent = state.frame === "image"
    ? "layout in pixels of the background"
    : "layout in metres on the ground, shown through the camera";
  const [width, height] = state.size;
  const margin = Math.round(0.08 * Math.max(width, height));
  const view = $("view");
  view.setAttribute("viewBox", `${-margin} ${-margin} ${width + 2 * margin} ${height + 2 * margin}`);
  view.setAttribute("width", width + 2 * margin);
  view.setAttribute("height", height + 2 * margin);
  const background = $("background");
  for (const [key, value] of Object.entries({ x: -0.5, y: -0.5, width, height })) background.setAttribute(key, value);
  const pointTool = $("point-tool");
  pointTool.disabled = Boolean(state.points_refused);
  if (state.points_refused) pointTool.title = state.points_refused;
  drawCamera(state);
  drawRegions(state.regions);
  const locked = $("locked");
  locked.replaceChildren(...state.locked.map((name) => Object.assign(document.createElement("li"), { textContent: name })));
  if (!state.locked.length) locked.appendChild(Object.assign(document.createElement("li"), { textContent: "nothing" }));
  render();
}

// the grid, the horizon and the camera's numbers: what measured points move
function drawCamera({ grid, horizon, camera }) {
  $("horizon").setAttribute("points", pointsAttribute(horizon));
  drawGrid(grid);
  $("camera").textContent = `focal ${camera.focal_px} px, ${camera.height_m} m above the ground`;
}

function drawGrid(grid) {
  const layer = $("grid-layer");
  layer.replaceChildren();
  for (const line of grid.lines) {
    const axis = Math.abs(line.metres) < 1e-9 ? " axis" : "";
    svgElement("polyline", { class: `grid${axis}`, points: pointsAttribute(line.pixels) }, layer);
  }
}

function drawRegions(regions) {
  const layer = $("region-layer");
  layer.replaceChildren();
  const list = $("regions");
  list.replaceChildren();
  regions.forEach((region, index) => {
    const colour = REGION_COLOURS[index % REGION_COLOURS.length];
    const [x, y, w, h] = region.crop;
    svgElement("rect", { class: "region", x: x - 0.5, y: y - 0.5, width: w, height: h, stroke: colour }, layer);
    for (const outline of region.outlines) {
      svgElement("polyline", { class: "region", points: pointsAttribute(outline), stroke: colour }, layer);
    }
    const label = svgElement("text", { class: "label", x: x + 4, y: y + 14 }, layer);
    label.textContent = region.name;
    const item = document.createElement("li");
    item.textContent = `${region.name}: crop ${w}x${h} at (${x}, ${y}), input ${region.input_size.join("x")}, ` +
      `people ${region.person_px[0]}-${region.person_px[1]} px`;
    list.appendChild(item);
  });
}

// ------------------------------------------------------------------------------------------------------ drawing

function elementPoints(kind, element) {
  if (kind === "walkable" || kind === "zones") return element.points;
  if (kind === "walls") return [element.start, element.end];
  if (kind === "points") return [element.pixel];
  return element.type === "cylinder" ? [element.base] : element.footprint;
}

function setElementPoint(kind, element, index, point) {
  if (kind === "walkable" || kind === "zones") element.points[index] = point;
  else if (kind === "walls") element[index === 0 ? "start" : "end"] = point;
  else if (kind === "points") element.pixel = point;
  else if (element.type === "cylinder") element.base = point;
  else element.footprint[index] = point;
}

function render() {
  const layer = $("element-layer");
  layer.replaceChildren();
  for (const kind of KINDS) {
    page.elements[kind].forEach((element, index) => {
      const selected = page.selected && page.selected.kind === kind && page.selected.index === index;
      const points = elementPoints(kind, element);
      const common = { "data-kind": kind, "data-index": index };
      let shape;
      if (kind === "walls") {
        shape = svgElement("polyline", { ...common, class: "wall", points: pointsAttribute(points) }, layer);
      } else if (kind === "points") {
        const [u, v] = points[0];
        shape = svgElement("circle", { ...common, class: "ground-point", cx: u, cy: v, r: 5 }, layer);
        svgElement("text", { class: "label", x: u + 7, y: v + 14 }, layer).textContent = `(${element.x}, ${element.y}) m`;
      } else if (kind === "obstacles" && element.type === "cylinder") {
        shape = svgElement("circle", { ...common, class: "obstacle", cx: points[0][0], cy: points[0][1], r: 6 }, layer);
      } else {
        const css = kind === "walkable" ? "walkable" : kind === "zones" ? "zone" : "obstacle";
        shape = svgElement("polygon", { ...common, class: css, points: pointsAttribute(points) }, layer);
      }
      if (selected) shape.classList.add("selected");
      if (element.name) {
        const [u, v] = points[0];
        svgElement("text", { class: "label", x: u + 6, y: v - 6 }, layer).textContent = element.name;
      }
    });
  }
  if (page.selected) {
    const { kind, index } = page.selected;
    elementPoints(kind, page.elements[kind][index]).forEach(([u, v], point) => {
      svgElement("circle", { class: "handle", cx: u, cy: v, r: 5, "data-handle-kind": kind,
                             "data-handle-index": index, "data-handle-point": point }, layer);
    });
  }
  const draft = $("draft-layer");
  draft.replaceChildren();
  if (page.draft.length) {
    svgElement("polyline", { class: "draft", points: pointsAttribute(page.draft) }, draft);
    for (const [u, v] of page.draft) svgElement("circle", { class: "handle", cx: u, cy: v, r: 3 }, draft);
  }
  $("finish").disabled = !["walkable", "zone"].includes(page.tool) || page.draft.length < 3;
  $("delete").disabled = !page.selected;
  showProperties();
}

function showProperties() {
  const fields = $("fields");
  fields.replaceChildren();
  $("nothing-selected").hidden = Boolean(page.selected);
  if (!page.selected) return;
  const { kind, index } = page.selected;
  const element = page.elements[kind][index];
  const names = kind === "walkable" ? [] : kind === "zones" ? ["name"] : kind === "points" ? ["x", "y"]
    : kind === "walls" ? ["name", "height", "thickness"]
    : element.type === "cylinder" ? ["name", "radius", "height"] : ["name", "height", "bottom"];
  const title = document.createElement("p");
  title.textContent = kind === "obstacles" ? `obstacle (${element.type})`
    : kind === "points" ? "ground point: where it is, measured" : kind.replace(/s$/, "");
  if (element.clipped) title.textContent += ": the part the camera sees";
  fields.appendChild(title);
  for (const name of names) {
    const label = document.createElement("label");
    label.textContent = name === "name" ? "name " : `${name} (m) `;
    const input = document.createElement("input");
    input.id = `prop-${name}`;
    input.type = name === "name" ? "text" : "number";
    if (name !== "name") input.step = kind === "points" ? "0.01" : "0.05";
    input.value = element[name] ?? "";
    input.addEventListener("change", () => {
      if (name === "name") {
        if (input.value) element.name = input.value;
        else delete element.name;
      } else {
        element[name] = Number(input.value);
      }
      element.edited = true;
      render();
    });
    label.appendChild(input);
    fields.appendChild(label);
  }
}

// ------------------------------------------------------------------------------------------------------ editing

function pixelOf(event) {
  const view = $("view");
  const point = view.createSVGPoint();
  point.x = event.clientX;
  point.y = event.clientY;
  const local = point.matrixTransform(view.getScreenCTM().inverse());
  return [Math.round(local.x * 10) / 10, Math.round(local.y * 10) / 10];
}

function chooseTool(tool) {
  page.tool = tool;
  page.draft = [];
  for (const button of document.querySelectorAll("#tools [data-tool]")) {
    button.classList.toggle("active", button.dataset.tool === tool);
  }
  render();
}

function add(kind, element) {
  page.elements[kind].push({ ...element, edited: true });
  page.selected = { kind, index: page.elements[kind].length - 1 };
  page.draft = [];
  render();
}

function nextZoneName() {
  const names = new Set(page.elements.zones.map((zone) => zone.name));
  let number = 1;
  while (names.has(`zone-${number}`)) number += 1;
  return `zone-${number}`;
}

function finishDraft() {
  // a double click finishes the shape after adding its point twice: consecutive repeats are one corner
  page.draft = page.draft.filter((point, index, all) =>
    index === 0 || Math.hypot(point[0] - all[index - 1][0], point[1] - all[index - 1][1]) > 1);
  if (page.draft.length < 3) return;
  if (page.tool === "walkable") add("walkable", { points: page.draft, source: null });
  else if (page.tool === "zone") add("zones", { name: nextZoneName(), frame: "image", points: page.draft, source: null });
}

function onClick(event) {
  if (event.target.dataset.handleKind) return;
  const pixel = pixelOf(event);
  if (page.tool === "select") {
    const kind = event.target.dataset.kind;
    page.selected = kind ? { kind, index: Number(event.target.dataset.index) } : null;
    render();
    return;
  }
  if (page.tool === "cylinder") {
    add("obstacles", { type: "cylinder", base: pixel, ...DEFAULTS.cylinder, source: null });
    return;
  }
  if (page.tool === "point") {
    add("points", { pixel, x: 0, y: 0, source: null });
    return;
  }
  page.draft.push(pixel);
  if (page.tool === "box" && page.draft.length === 4) {
    add("obstacles", { type: "box", footprint: page.draft, ...DEFAULTS.box, source: null });
  } else if (page.tool === "wall" && page.draft.length === 2) {
    add("walls", { start: page.draft[0], end: page.draft[1], ...DEFAULTS.wall, source: null });
  } else {
    render();
  }
}

function onPointerDown(event) {
  const target = event.target;
  if (!target.dataset.handleKind) return;
  page.drag = { kind: target.dataset.handleKind, index: Number(target.dataset.handleIndex),
                point: Number(target.dataset.handlePoint) };
  $("view").setPointerCapture(event.pointerId);
  event.preventDefault();
}

function onPointerMove(event) {
  if (page.drag) {
    const { kind, index, point } = page.drag;
    const element = page.elements[kind][index];
    setElementPoint(kind, element, point, pixelOf(event));
    element.edited = true;
    render();
    return;
  }
  if (!$("show-figures").checked) return;
  clearTimeout(page.figureTimer);
  const [u, v] = pixelOf(event);
  page.figureTimer = setTimeout(() => showFigures(u, v), FIGURE_DELAY_MS);
}

function onPointerUp(event) {
  if (!page.drag) return;
  page.drag = null;
  $("view").releasePointerCapture(event.pointerId);
}

async function showFigures(u, v) {
  try {
    const answer = await request("GET", `api/figures?u=${u}&v=${v}`);
    const layer = $("figure-layer");
    layer.replaceChildren();
    if (!answer.ground) {
      $("ground").textContent = `(${u}, ${v}): above the horizon`;
      return;
    }
    answer.figures.forEach((figure, index) => {
      for (const line of figure.lines) {
        svgElement("polyline", { class: index ? "figure tall" : "figure", points: pointsAttribute(line) }, layer);
      }
    });
    const heights = answer.figures.map((figure) => `${figure.stature_m} m: ${figure.height_px} px`).join(", ");
    $("ground").textContent = `pixel (${u}, ${v}), ground (${answer.ground[0]}, ${answer.ground[1]}) m; ${heights}`;
  } catch (error) {
    say(`figures: ${error.message}`, "error");
  }
}

function deleteSelected() {
  if (!page.selected) return;
  const { kind, index } = page.selected;
  const [element] = page.elements[kind].splice(index, 1);
  if (element.source !== null && element.source !== undefined) page.removed[kind].push(element.source);
  page.selected = null;
  render();
}

function edit() {
  const strip = ({ clipped, ...element }) => element;
  return { ...Object.fromEntries(KINDS.map((kind) => [kind, page.elements[kind].map(strip)])), removed: page.removed };
}

async function check() {
  say("checking…");
  try {
    const answer = await request("POST", "api/check", edit());
    drawRegions(answer.regions);
    drawCamera(answer);
    say(`the scene loads: walkable ${answer.walkable_area_m2} m², ${answer.regions.length} regions` +
        (answer.zones.length ? `, zones ${answer.zones.join(", ")}` : "") + " (not saved)", "ok");
  } catch (error) {
    say(error.message, "error");
  }
}

async function save() {
  say("saving…");
  try {
    const state = await request("POST", "api/save", edit());
    adopt(state);
    say(`saved ${state.path}`, "ok");
  } catch (error) {
    say(`not saved: ${error.message}`, "error");
  }
}

function start() {
  for (const button of document.querySelectorAll("#tools [data-tool]")) {
    button.addEventListener("click", () => chooseTool(button.dataset.tool));
  }
  $("finish").addEventListener("click", finishDraft);
  $("delete").addEventListener("click", deleteSelected);
  $("check").addEventListener("click", check);
  $("save").addEventListener("click", save);
  const view = $("view");
  view.addEventListener("click", onClick);
  view.addEventListener("dblclick", finishDraft);
  view.addEventListener("pointerdown", onPointerDown);
  view.addEventListener("pointermove", onPointerMove);
  view.addEventListener("pointerup", onPointerUp);
  document.addEventListener("keydown", (event) => {
    if (event.target.tagName === "INPUT") return;
    if (event.key === "Enter") finishDraft();
    else if (event.key === "Escape") chooseTool(page.tool);
    else if (event.key === "Delete" || event.key === "Backspace") deleteSelected();
  });
  $("show-grid").addEventListener("change", (event) => { $("grid-layer").style.display = event.target.checked ? "" : "none"; });
  $("show-regions").addEventListener("change", (event) => { $("region-layer").style.display = event.target.checked ? "" : "none"; });
  $("show-figures").addEventListener("change", (event) => {
    if (!event.target.checked) $("figure-layer").replaceChildren();
  });
  request("GET", "api/state").then((state) => {
    adopt(state);
    document.body.dataset.ready = "true";
  }).catch((error) => say(`cannot load the scene: ${error.message}`, "error"));
}

start();
