// A scenario's map from above as SVG, from GET /api/v1/scenarios/{id}/world: walls, obstacles
// (furniture), doors, movable objects, locations, social spaces and agents' start poses, with x to the right and y up
// as in the map frame, and a scale bar. Pages add paths and markers on top (trajectories, people, the
// robot). Labels never overlap: each takes the first free place near its point, or is left out (its
// mark keeps the name as a tooltip).
const SVG = 'http://www.w3.org/2000/svg';
/** As `svg.map .map-label` in style.css: labels are measured in this font before they are placed. */
const LABEL_FONT = '11px system-ui, sans-serif';
const LABEL_HEIGHT = 13;
/** Scale bar lengths (m) to choose from: the longest that fits in SCALE_BAR_MAX_PX. */
const SCALE_BAR_LENGTHS = [0.1, 0.2, 0.5, 1, 2, 5, 10, 20, 50, 100, 200, 500];
const SCALE_BAR_MAX_PX = 110;
/** A movable object (a 4 cm cube on a 7 m map is 3 px) is drawn at least this wide, px. */
const MIN_OBJECT_PX = 4;

let measuring = null;
function labelWidth(text) {
  measuring ??= document.createElement('canvas').getContext('2d');
  measuring.font = LABEL_FONT;
  return measuring.measureText(text).width;
}

/** "0.5 m", "2 m", "12.5 m". */
const formatMetres = (metres) => `${Number(metres.toFixed(2))} m`;

const overlaps = (a, b) => a.x < b.x + b.width && b.x < a.x + a.width && a.y < b.y + b.height && b.y < a.y + a.height;

function svg(tag, attributes = {}, parent = null) {
  const element = document.createElementNS(SVG, tag);
  for (const [name, value] of Object.entries(attributes)) element.setAttribute(name, String(value));
  if (parent) parent.append(element);
  return element;
}

/** Colours of agents and layers, shared by every view of a map. */
export const palette = {
  wall: '#5b6270',
  obstacle: '#b08a64',
  door: '#7a5236',
  location: '#2f7d4f',
  space: '#8a5cb8',
  object: '#b5307a',
  human: '#2f6fd1',
  robot: '#e07b18',
  /** The robot's orange is too light for text (4.5:1 on the labels' white halo): its labels take this. */
  robotText: '#9c530c',
  path: ['#2f6fd1', '#d1492f', '#2f9d5b', '#c99016', '#7d4fb8', '#1f9aa6'],
};

export class MapView {
  /**
   * Draws `world` into `container`, `width` pixels wide (the height follows the map's shape, at most
   * `maxHeight`). Options: labels (names of locations and spaces, default true), starts (agents' and
   * movable objects' start poses, default true).
   */
  constructor(container, world, { width = 640, maxHeight = 480, labels = true, starts = true } = {}) {
    this.world = world;
    const [x0, y0] = world.bounds.min;
    const [x1, y1] = world.bounds.max;
    const margin = 0.3;
    this.x0 = x0 - margin;
    this.y1 = y1 + margin;
    const spanX = x1 - x0 + 2 * margin, spanY = y1 - y0 + 2 * margin;
    this.scale = Math.min(width / spanX, maxHeight / spanY);
    this.width = spanX * this.scale;
    this.height = spanY * this.scale;
    this.svg = svg('svg', { class: 'map', viewBox: `0 0 ${this.width} ${this.height}`, width: this.width, height: this.height, role: 'img' });
    svg('rect', { x: 0, y: 0, width: this.width, height: this.height, class: 'map-floor' }, this.svg);
    /** Boxes (SVG px) that labels keep clear of: the scale bar and the labels placed so far. */
    this.taken = [];
    const base = svg('g', { class: 'map-base' }, this.svg);
    for (const obstacle of world.obstacles) {
      const polygon = svg('polygon', { points: obstacle.polygon.map(([x, y]) => this.point(x, y).join(',')).join(' '),
        fill: obstacle.name.startsWith('wall ') ? palette.wall : palette.obstacle, opacity: 0.85 }, base);
      svg('title', {}, polygon).textContent = obstacle.name + (obstacle.mesh ? ` (${obstacle.mesh})` : '');
    }
    for (const wall of world.walls) {
      // Walls of a map from an image (obstacles' own edges are drawn as the polygons above).
      if (world.obstacles.length === 0) this.line(wall.from, wall.to, { stroke: palette.wall, 'stroke-width': 2 }, base);
    }
    for (const door of world.doors) this.line(door.from, door.to, { stroke: palette.door, 'stroke-width': 4, class: 'map-door' }, base);
    if (starts) for (const object of world.objects) this.object(object, base);
    this.layers = { spaces: svg('g', {}, this.svg), locations: svg('g', {}, this.svg), paths: svg('g', {}, this.svg), marks: svg('g', {}, this.svg),
      labels: svg('g', {}, this.svg) };
    this.scaleBar();
    for (const space of world.social_spaces) {
      const [cx, cy] = this.point(space.centre.x, space.centre.y);
      const ring = svg('circle', { cx, cy, r: 0.6 * this.scale, fill: 'none', stroke: palette.space, 'stroke-dasharray': '4 3' }, this.layers.spaces);
      svg('title', {}, ring).textContent = `social space ${space.name}`;
      for (const slot of space.slots) {
        const [sx, sy] = this.point(slot.x, slot.y);
        svg('circle', { cx: sx, cy: sy, r: 3, fill: palette.space }, this.layers.spaces);
      }
      if (labels) this.text(space.centre.x, space.centre.y + 0.7, space.name, palette.space);
    }
    for (const location of world.locations) {
      const [lx, ly] = this.point(location.x, location.y);
      const ring = svg('circle', { cx: lx, cy: ly, r: Math.max(location.radius * this.scale, 3), fill: 'none', stroke: palette.location }, this.layers.locations);
      svg('title', {}, ring).textContent = `location ${location.name}`;
      if (labels) this.text(location.x, location.y - 0.35, location.name, palette.location);
    }
    this.svg.setAttribute('aria-label', `Map of ${world.name}, ${formatMetres(spanX - 2 * margin)} by ${formatMetres(spanY - 2 * margin)}`);
    if (starts) {
      for (const agent of world.agents) this.agent(agent.start.x, agent.start.y, agent.start.theta, agent.kind, agent.radius, agent.id, this.layers.marks, 0.5);
    }
    container.append(this.svg);
  }

  /** Map coordinates → SVG pixels. */
  point(x, y) {
    return [(x - this.x0) * this.scale, (this.y1 - y) * this.scale];
  }

  line(from, to, attributes, parent) {
    const [ax, ay] = this.point(from[0], from[1]);
    const [bx, by] = this.point(to[0], to[1]);
    return svg('line', { x1: ax, y1: ay, x2: bx, y2: by, ...attributes }, parent);
  }

  /**
   * A label centred on (x, y) in map coordinates, or as near as it fits without covering another label
   * or the scale bar: a line up or down, or beside. Returns the element, or null when no place is free.
   */
  text(x, y, label, colour) {
    const [tx, ty] = this.point(x, y);
    const width = labelWidth(label) + 2;
    const side = width / 2 + 4;
    const places = [[0, 0], [0, LABEL_HEIGHT], [0, -LABEL_HEIGHT], [side, 0], [-side, 0], [0, 2 * LABEL_HEIGHT], [0, -2 * LABEL_HEIGHT],
      [side, LABEL_HEIGHT], [-side, LABEL_HEIGHT], [side, -LABEL_HEIGHT], [-side, -LABEL_HEIGHT]];
    for (const [dx, dy] of places) {
      // The box of text anchored at its middle and its baseline.
      const box = { x: tx + dx - width / 2, y: ty + dy - LABEL_HEIGHT + 3, width, height: LABEL_HEIGHT };
      const inside = box.x >= 0 && box.y >= 0 && box.x + box.width <= this.width && box.y + box.height <= this.height;
      if (!inside || this.taken.some((other) => overlaps(box, other))) continue;
      this.taken.push(box);
      const element = svg('text', { x: tx + dx, y: ty + dy, fill: colour, 'text-anchor': 'middle', class: 'map-label' }, this.layers.labels);
      element.textContent = label;
      return element;
    }
    return null;
  }

  /** A movable object at its pose, from above: a box's footprint turned by its yaw, else a disc of its radius. */
  object({ name, shape, pose }, parent) {
    const [cx, cy] = this.point(pose.x, pose.y);
    const style = { fill: palette.object, stroke: '#fff', 'stroke-width': 0.75, class: 'map-object' };
    let mark;
    if (shape.kind === 'box') {
      const [width, depth] = shape.size.map((size) => Math.max(size * this.scale, MIN_OBJECT_PX));
      // SVG's y points down: a turn to the left in the map is a negative angle here.
      mark = svg('rect', { x: cx - width / 2, y: cy - depth / 2, width, height: depth,
        transform: `rotate(${(-pose.yaw * 180) / Math.PI} ${cx} ${cy})`, ...style }, parent);
    } else {
      mark = svg('circle', { cx, cy, r: Math.max(shape.radius * this.scale, MIN_OBJECT_PX / 2), ...style }, parent);
    }
    svg('title', {}, mark).textContent = `object ${name} (${shape.kind})`;
  }

  /** A bar of a round length in metres in the bottom left corner, on a pale backing. */
  scaleBar() {
    const metres = SCALE_BAR_LENGTHS.filter((length) => length * this.scale <= SCALE_BAR_MAX_PX).pop() ?? SCALE_BAR_LENGTHS[0];
    const length = metres * this.scale;
    const [left, bottom] = [8, this.height - 6];
    const text = formatMetres(metres);
    const box = { x: left - 4, y: bottom - 22, width: Math.max(length, labelWidth(text)) + 8, height: 24 };
    const group = svg('g', { class: 'map-scale', 'data-metres': metres }, this.svg);
    svg('rect', { ...box, rx: 3, class: 'map-scale-backing' }, group);
    svg('path', { d: `M ${left} ${bottom - 5} V ${bottom} H ${left + length} V ${bottom - 5}`, class: 'map-scale-bar' }, group);
    svg('text', { x: left, y: bottom - 8, class: 'map-label map-scale-text' }, group).textContent = text;
    this.taken.push(box);
  }

  /** An agent as a disc with a heading tick; returns the SVG group (for removing or moving it). */
  agent(x, y, theta, kind, radius = 0.3, label = '', parent = this.layers.marks, opacity = 1) {
    const group = svg('g', { class: `map-agent ${kind}`, opacity }, parent);
    const [cx, cy] = this.point(x, y);
    const colour = kind === 'robot' ? palette.robot : palette.human;
    svg('circle', { cx, cy, r: Math.max(radius * this.scale, 3), fill: colour, 'fill-opacity': 0.35, stroke: colour }, group);
    const [hx, hy] = this.point(x + radius * 1.6 * Math.cos(theta), y + radius * 1.6 * Math.sin(theta));
    svg('line', { x1: cx, y1: cy, x2: hx, y2: hy, stroke: colour, 'stroke-width': 2 }, group);
    if (label) svg('title', {}, group).textContent = label;
    return group;
  }

  /** A polyline through [[x, y], …] (a trajectory); returns the element. */
  path(points, { colour = palette.path[0], width = 2, dash = null, label = '' } = {}) {
    const element = svg('polyline', { points: points.map(([x, y]) => this.point(x, y).join(',')).join(' '), fill: 'none',
      stroke: colour, 'stroke-width': width, 'stroke-linejoin': 'round', ...(dash ? { 'stroke-dasharray': dash } : {}) }, this.layers.paths);
    if (label) svg('title', {}, element).textContent = label;
    return element;
  }

  /** Removes what pages added (paths and agents), keeping the map and its labels. */
  clear() {
    this.layers.paths.replaceChildren();
    this.layers.marks.replaceChildren();
  }
}
