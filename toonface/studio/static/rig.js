// A face's web rig (toon/web_rig.py) evaluated in the page: motor values in, the frame's SVG out,
// line for line what toon/svg.py's geometry_svg writes for the same values (the golden test holds
// the two pictures together). Every page that draws a face from motors (the room's viewer, the
// exported player, OBS's view) draws through this module; the numbers come from the Python rig,
// the formulas are the ones toon/rig.py and toon/formulas.py state (the ToonFace appendix A1).
"use strict";
(() => {
  const TINY = 1e-9;

  function fmt(x, decimals = 3) {
    // toon/svg.py's _fmt: fixed decimals, trailing zeros and point dropped, never "-0"
    let text = x.toFixed(decimals);
    if (text.includes(".")) text = text.replace(/0+$/, "").replace(/\.$/, "");
    return text === "-0" || text === "" ? "0" : text;
  }

  function roundEven(x) {
    // Python's round(): halves go to the even neighbour
    const r = Math.round(x);
    return Math.abs(x % 1) === 0.5 && r % 2 !== 0 ? r - 1 : r;
  }

  function paint(color) {
    if (!color) return "none";
    return "#" + color.slice(0, 3).map((c) => roundEven(c * 255).toString(16).padStart(2, "0")).join("");
  }

  function opacity(attr, color) {
    return color && color[3] < 1 ? ` ${attr}="${fmt(color[3])}"` : "";
  }

  function quoteattr(text) {
    // xml.sax.saxutils.quoteattr
    let s = text.replace(/&/g, "&amp;").replace(/</g, "&lt;").replace(/>/g, "&gt;")
      .replace(/\n/g, "&#10;").replace(/\r/g, "&#13;").replace(/\t/g, "&#9;");
    if (s.includes('"')) {
      if (s.includes("'")) return `"${s.replace(/"/g, "&quot;")}"`;
      return `'${s}'`;
    }
    return `"${s}"`;
  }

  function csrTimes(m, x, out, rows) {
    // out[rows[i]] = (m @ x)[i] for a CSR matrix m and points x (Float64Array, 2 a point)
    const {indptr, indices, data} = m;
    for (let i = 0; i < indptr.length - 1; i++) {
      let sx = 0, sy = 0;
      for (let k = indptr[i]; k < indptr[i + 1]; k++) {
        const j = indices[k], w = data[k];
        sx += w * x[2 * j];
        sy += w * x[2 * j + 1];
      }
      const r = rows ? rows[i] : i;
      out[2 * r] = sx;
      out[2 * r + 1] = sy;
    }
  }

  class Rig {
    // a face bound for drawing: `data` is a web rig (toon/web_rig.py's JSON)
    constructor(data) {
      if (data.format !== "toonface-web-rig" || data.version !== 1) throw new Error("not a toonface web rig (version 1)");
      this.data = data;
      this.codes = data.codes;
      this.rest = new Float64Array(data.rest.flat());
      this.points = data.rest.length;
    }

    controlPoints(v) {
      // the control points (Float64Array, x y a point) for a full frame `v` (one value a code)
      const d = this.data, pts = this.rest.slice();
      for (const [col, row, axis, lo, hi] of d.driven) pts[2 * row + axis] = lo + v[col] * (hi - lo);
      for (const [col, row, ax, ay, sx, sy] of d.moves) {
        pts[2 * row] += ax + v[col] * sx;
        pts[2 * row + 1] += ay + v[col] * sy;
      }
      const gaze = this.gaze(v);
      d.pupilRows.forEach((row, eye) => {
        pts[2 * row] += d.eyeRadius * Math.sin(gaze[eye][0]);
        pts[2 * row + 1] += d.eyeRadius * Math.sin(gaze[eye][1]);
      });
      for (const [up, low] of d.lids) {  // lids that cross meet half-way: a closed eye
        if (pts[2 * up + 1] < pts[2 * low + 1]) pts[2 * up + 1] = pts[2 * low + 1] = (pts[2 * up + 1] + pts[2 * low + 1]) / 2;
      }
      return pts;
    }

    gaze(v) {
      // each pupil's gaze angles in radians: [[horizontal, vertical], ...]
      const d = this.data;
      return d.gazeColumns.map((cols, eye) => cols.map((col, axis) =>
        (d.gazeLow[eye][axis] + v[col] * d.gazeSpan[eye][axis]) * Math.PI / 180));
    }

    shown(v, pts) {
      // the values that decide what is shown: each upper lid's value is how open its eye is
      const out = v.slice();
      for (const [up, low, column, lo, hi, rest] of this.data.lids) {
        if (hi !== lo) {
          const height = rest + Math.max(pts[2 * up + 1] - pts[2 * low + 1], 0);
          out[column] = Math.min(v[column], (height - lo) / (hi - lo));
        }
      }
      return out;
    }

    vertices(v) {
      // every vertex of the frame `v` (Float64Array, x y a vertex), items in drawing order
      const d = this.data, plan = d.plan, out = new Float64Array(2 * plan.size);
      const pts = this.controlPoints(v), gaze = this.gaze(v);
      plan.staticAt.forEach((at, i) => { out[2 * at] = plan.staticXy[i][0]; out[2 * at + 1] = plan.staticXy[i][1]; });
      if (plan.lines) this.followLines(plan.lines, plan.lineAt, pts, out);
      if (plan.arcs) this.followArcs(plan.arcs, plan.arcAt, pts, out);
      plan.pupilAt.forEach((at, i) => {
        const row = plan.pupilRow[i], g = gaze[plan.pupilEye[i]];
        out[2 * at] = pts[2 * row] + plan.pupilOffset[i][0] * Math.cos(g[0]);
        out[2 * at + 1] = pts[2 * row + 1] + plan.pupilOffset[i][1] * Math.cos(g[1]);
      });
      plan.pointAt.forEach((at, i) => {  // A1.5-A1.6
        const p = v[plan.pointMotor[i]], lo = plan.pointMin[i], hi = plan.pointMax[i];
        out[2 * at] = lo[0] + p * (hi[0] - lo[0]);
        out[2 * at + 1] = lo[1] + p * (hi[1] - lo[1]);
      });
      if (plan.operator) csrTimes(plan.operator, this.outlineInputs(pts), out, plan.componentAt);
      for (const change of d.animated) this.animate(change, v, out);
      const h = d.head;
      const yaw = h.yaw[0] + v[h.yawColumn] * (h.yaw[1] - h.yaw[0]);
      const pitch = h.pitch[0] + v[h.pitchColumn] * (h.pitch[1] - h.pitch[0]);
      if ((yaw || pitch) && plan.movingAt.length) this.headTurn(out, yaw, pitch);
      if (h.tilt && v[h.tiltColumn] !== 0.5) {
        const angle = (2 * v[h.tiltColumn] - 1) * h.tilt * Math.PI / 180;
        this.turn(out, 0, plan.size, h.pivot, Math.cos(angle), Math.sin(angle));
      }
      return {out, pts};
    }

    followLines(b, at, pts, out) {
      // A1.1-A1.4
      for (let i = 0; i < at.length; i++) {
        const h0 = pts[2 * b.start[i]], v0 = pts[2 * b.start[i] + 1], h1 = pts[2 * b.end[i]], v1 = pts[2 * b.end[i] + 1];
        const dh = Math.abs(h1 - h0) > TINY ? h1 - h0 : TINY;
        const slope = (v1 - v0) / dh, intercept = v0 - slope * h0;
        const x = h0 + b.vrl[i] * (h1 - h0);
        out[2 * at[i]] = x;
        out[2 * at[i] + 1] = x * slope + intercept + b.d[i];
      }
    }

    followArcs(b, at, pts, out) {
      // the parabola through a corner, a middle and the other corner (toon/formulas.py follow_arcs)
      const safe = (x) => (Math.abs(x) > TINY ? x : TINY);
      for (let i = 0; i < at.length; i++) {
        const xa = pts[2 * b.a[i]], ya = pts[2 * b.a[i] + 1], xb = pts[2 * b.b[i]], yb = pts[2 * b.b[i] + 1];
        const xm = pts[2 * b.m[i]];
        let ym = pts[2 * b.m[i] + 1];
        const yOther = pts[2 * b.other[i] + 1], hole = b.gap[i] > 0;
        const yUp = b.upper[i] ? ym : yOther, yLow = b.upper[i] ? yOther : ym;
        const openness = Math.min(Math.max((yUp - yLow) / (hole ? b.gap[i] : 1), 0), 1);
        if (hole && yUp < yLow) ym = (yUp + yLow) / 2;
        const x = xa + b.vrl[i] * (xb - xa);
        const y = ya * (x - xm) * (x - xb) / safe((xa - xm) * (xa - xb))
          + ym * (x - xa) * (x - xb) / safe((xm - xa) * (xm - xb))
          + yb * (x - xa) * (x - xm) / safe((xb - xa) * (xb - xm));
        out[2 * at[i]] = x;
        out[2 * at[i] + 1] = y + b.d[i] * (hole ? openness : 1);
      }
    }

    outlineInputs(pts) {
      // every component's defining points (a skeleton's body) at control points `pts`
      const plan = this.data.plan, n = plan.definingRow.length, moved = new Float64Array(2 * n);
      plan.definingRow.forEach((row, i) => {
        moved[2 * i] = (row >= 0 ? pts[2 * row] : 0) + plan.definingOffset[i][0];
        moved[2 * i + 1] = (row >= 0 ? pts[2 * row + 1] : 0) + plan.definingOffset[i][1];
      });
      if (plan.definingBlend) {  // slaves of several masters: each one's share of the motion
        const delta = pts.map((p, k) => p - this.rest[k]), add = new Float64Array(2 * n);
        csrTimes(plan.definingBlend, delta, add, null);
        for (let k = 0; k < 2 * n; k++) moved[k] += add[k];
      }
      const inputs = new Float64Array(2 * plan.operator.shape[1]);
      plan.directFrom.forEach((from, i) => {
        inputs[2 * plan.directTo[i]] = moved[2 * from];
        inputs[2 * plan.directTo[i] + 1] = moved[2 * from + 1];
      });
      for (const s of plan.skeletons) this.body(s, moved, inputs);
      return inputs;
    }

    body(s, moved, inputs) {
      // a skeleton's body points for its skeleton's points (toon/skeleton.py)
      const [t0] = s.taken, [g0] = s.given;
      const sk = (k) => [moved[2 * (t0 + k)], moved[2 * (t0 + k) + 1]];
      s.bodyRest.forEach((rest, i) => {
        let x = rest[0], y = rest[1];
        if (s.kind === "point") {
          const k = s.nearest[i], [px, py] = sk(k);
          if (s.moves[i]) { x += px - s.skeletonRest[k][0]; y += py - s.skeletonRest[k][1]; }
        } else if (s.moves[i]) {
          const [ax, ay] = sk(s.start[i]), [bx, by] = sk(s.end[i]);
          const ex = bx - ax, ey = by - ay, length = Math.hypot(ex, ey);
          const ux = ex / (length > 1e-12 ? length : 1), uy = ey / (length > 1e-12 ? length : 1);
          x = ax + s.t[i] * ex - s.d[i] * uy;
          y = ay + s.t[i] * ey + s.d[i] * ux;
        }
        inputs[2 * (g0 + i)] = x;
        inputs[2 * (g0 + i) + 1] = y;
      });
    }

    animate(change, v, out) {
      // a component scaled, then turned, then moved by its motors (toon/components.py)
      const [a, b] = change.at;
      const lerp = (p, k) => p.at0[k] + v[p.column] * (p.at1[k] - p.at0[k]);
      if (change.scale) {
        const s = change.scale, o = s.origin, fx = lerp(s, 0), fy = lerp(s, 1);
        for (let i = a; i < b; i++) {
          out[2 * i] = o[0] + (out[2 * i] - o[0]) * fx;
          out[2 * i + 1] = o[1] + (out[2 * i + 1] - o[1]) * fy;
        }
      }
      if (change.rotate) {
        const angle = lerp(change.rotate, 0) * Math.PI / 180;
        this.turn(out, a, b, change.rotate.origin, Math.cos(angle), Math.sin(angle));
      }
      if (change.translate) {
        const dx = lerp(change.translate, 0), dy = lerp(change.translate, 1);
        for (let i = a; i < b; i++) { out[2 * i] += dx; out[2 * i + 1] += dy; }
      }
    }

    turn(out, a, b, origin, c, s) {
      // vertices a..b turned counter-clockwise about `origin` (cos c, sin s)
      for (let i = a; i < b; i++) {
        const x = out[2 * i] - origin[0], y = out[2 * i + 1] - origin[1];
        out[2 * i] = origin[0] + x * c - y * s;
        out[2 * i + 1] = origin[1] + x * s + y * c;
      }
    }

    headTurn(out, yawDeg, pitchDeg) {
      // toon/formulas.py head_turn: pitch, then yaw, projected orthographically
      const plan = this.data.plan, pivot = this.data.head.pivot;
      const yaw = yawDeg * Math.PI / 180, pitch = pitchDeg * Math.PI / 180;
      plan.movingAt.forEach((at, i) => {
        const depth = plan.movingDepth[i], x = out[2 * at] - pivot[0], y = out[2 * at + 1] - pivot[1];
        const y2 = y * Math.cos(pitch) + depth * Math.sin(pitch);
        const z2 = -y * Math.sin(pitch) + depth * Math.cos(pitch);
        out[2 * at] = x * Math.cos(yaw) + z2 * Math.sin(yaw) + pivot[0];
        out[2 * at + 1] = y2 + pivot[1];
      });
    }

    geometry(v) {
      // the frame's items: [{item (its paint), vertices (Float64Array)}], hidden ones left out
      const d = this.data, {out, pts} = this.vertices(v);
      const decides = d.switched.length ? this.shown(v, pts) : v;
      const hidden = new Set(d.switched.filter(([, col, lo, hi]) => !(lo <= decides[col] && decides[col] <= hi))
        .map(([key]) => key));
      const items = [];
      d.plan.slices.forEach(([a, b], key) => {
        if (!hidden.has(key)) items.push({item: d.items[key], vertices: out.subarray(2 * a, 2 * b)});
      });
      return items;
    }

    svg(v, size = [512, 512], decimals = 3) {
      // the frame as toon/svg.py's geometry_svg writes it (a string, one line a drawn item)
      return svgOf(this.geometry(v), this.data.viewbox, this.data.background, size, decimals);
    }
  }

  function coords(vertices, decimals, index) {
    // "x,y x,y ..." with y turned down (SVG), of every vertex or of those at `index`
    const out = [];
    const take = index || Array.from({length: vertices.length / 2}, (_, i) => i);
    for (const i of take) out.push(`${fmt(vertices[2 * i], decimals)},${fmt(-vertices[2 * i + 1], decimals)}`);
    return out.join(" ");
  }

  function visibleRuns(visible, closed) {
    // toon/curves.py visible_runs: maximal runs of visible edges as [first point, last point]
    const e = visible.length;
    if (closed && visible.every(Boolean)) return [[0, 0]];
    let order = Array.from({length: e}, (_, k) => k);
    if (closed) {
      const firstHidden = Math.max(visible.indexOf(false), 0);
      order = order.map((k) => (firstHidden + 1 + k) % e);
    }
    const runs = [];
    let start = null;
    for (const i of order) {
      if (visible[i] && start === null) start = i;
      if (!visible[i] && start !== null) { runs.push([start, i]); start = null; }
    }
    if (start !== null) {
      const last = order[order.length - 1] + 1;
      runs.push([start, closed ? last % e : last]);
    }
    return runs;
  }

  function strokePaths(item, vertices, decimals) {
    const n = vertices.length / 2, edges = item.closed ? n : n - 1;
    const visible = item.edgeVisible || new Array(Math.max(edges, 0)).fill(true);
    const paths = [];
    for (const [first, last] of visibleRuns(visible, item.closed)) {
      if (item.closed && visible.every(Boolean)) { paths.push(`M${coords(vertices, decimals)}Z`); continue; }
      const count = (item.closed ? ((last - first) % n + n) % n : last - first) + 1;
      const index = Array.from({length: count}, (_, k) => (first + k) % n);
      paths.push(`M${coords(vertices, decimals, index)}`);
    }
    return paths;
  }

  function placed(item, vertices, number, decimals) {
    // a <use> of picture `number` taken onto the item's corners (toon/images.py pixel_affine)
    const [w, h] = item.picture.size;
    const tl = [vertices[0], -vertices[1]], tr = [vertices[2], -vertices[3]], bl = [vertices[6], -vertices[7]];
    const a = (tr[0] - tl[0]) / w, b = (tr[1] - tl[1]) / w, c = (bl[0] - tl[0]) / h, d = (bl[1] - tl[1]) / h;
    const matrix = [a, b, c, d, tl[0], tl[1]].map((x) => fmt(x, decimals + 3)).join(" ");
    const fade = item.opacity < 1 ? ` opacity="${fmt(item.opacity)}"` : "";
    return `<use href="#picture-${number}" transform="matrix(${matrix})"${fade}/>`;
  }

  function svgOf(geometry, viewbox, background, size, decimals) {
    const [xmin, ymin, xmax, ymax] = viewbox, w = xmax - xmin, h = ymax - ymin;
    const view = `${fmt(xmin)} ${fmt(-ymax)} ${fmt(w)} ${fmt(h)}`;
    const holes = new Map();
    for (const {item, vertices} of geometry) {
      if (!item.maskWrite) continue;
      if (!holes.has(item.maskWrite)) holes.set(item.maskWrite, []);
      holes.get(item.maskWrite).push(`<polygon points="${coords(vertices, decimals)}"/>`);
    }
    const big = `x="${fmt(xmin - 10 * w)}" y="${fmt(-ymax - 10 * h)}" width="${fmt(21 * w)}" height="${fmt(21 * h)}"`;
    const pictures = new Map(), shown = [];
    for (const {item} of geometry) {
      if (item.picture && !pictures.has(item.picture.href)) {
        pictures.set(item.picture.href, pictures.size);
        const [pw, ph] = item.picture.size;
        shown.push(`<image id="picture-${pictures.get(item.picture.href)}" width="${pw}" height="${ph}" `
          + `preserveAspectRatio="none" href="${item.picture.href}"/>`);
      }
    }
    const defs = [];
    if (holes.size) {
      const black = [...holes.values()].flat().map((p) => p.replace("<polygon ", '<polygon fill="black" fill-rule="evenodd" ')).join("");
      defs.push(`<mask id="no-holes" maskUnits="userSpaceOnUse" ${big}><rect ${big} fill="white"/>${black}</mask>`);
      for (const [group, polys] of holes) {
        defs.push(`<clipPath id="group-${group}">` + polys.map((p) => p.replace("<polygon ", '<polygon clip-rule="evenodd" ')).join("") + "</clipPath>");
      }
    }
    const body = [`<rect ${big} fill="${paint(background)}"${opacity("fill-opacity", background)}/>`];
    for (const {item, vertices} of geometry) {
      const name = item.name ? ` data-name=${quoteattr(item.name)}` : "";
      let wrap = "";
      if (item.maskTest === 0) wrap = holes.size ? ' mask="url(#no-holes)"' : "";
      else if (item.maskTest !== null && item.maskTest !== undefined) {
        if (!holes.has(item.maskTest)) continue;  // clipped to a group with no holes: nothing shows
        wrap = ` clip-path="url(#group-${item.maskTest})"`;
      }
      const parts = [];
      if (item.fill && item.closed) {
        parts.push(`<polygon points="${coords(vertices, decimals)}" fill="${paint(item.fill)}"`
          + `${opacity("fill-opacity", item.fill)} fill-rule="evenodd"/>`);
      }
      if (item.stroke && item.width > 0) {
        for (const d of strokePaths(item, vertices, decimals)) {
          parts.push(`<path d="${d}" fill="none" stroke="${paint(item.stroke)}"`
            + `${opacity("stroke-opacity", item.stroke)} stroke-width="${fmt(item.width)}" `
            + 'stroke-linejoin="miter" stroke-miterlimit="4" stroke-linecap="butt"/>');
        }
      }
      if (item.picture && vertices.length === 8) parts.push(placed(item, vertices, pictures.get(item.picture.href), decimals));
      if (parts.length) body.push(`<g class="${item.kind}"${name}${wrap}>` + parts.join("") + "</g>");
    }
    return `<svg xmlns="http://www.w3.org/2000/svg" width="${size[0]}" height="${size[1]}" viewBox="${view}" `
      + 'preserveAspectRatio="xMidYMid meet">\n'
      + (shown.length ? `<defs>${shown.join("")}</defs>\n` : "")
      + (defs.length ? `<defs>${defs.join("")}</defs>\n` : "")
      + body.join("\n") + "\n</svg>\n";
  }

  window.toonRig = {Rig, svgOf, fmt};
})();
