/* seapass explore: a small SVG plotter (line plots, bands, a raster region, a 1-D interval bar).
 * No dependencies; everything is drawn as SVG text so the page works offline. */
"use strict";

const Plots = (() => {
  const NS = "http://www.w3.org/2000/svg";
  const M = { l: 54, r: 12, t: 20, b: 36 };

  function fmt(v, digits = 4) {
    if (v === null || v === undefined || Number.isNaN(v)) return "—";
    if (!Number.isFinite(v)) return v > 0 ? "∞" : "−∞";
    if (v === 0) return "0";
    const a = Math.abs(v);
    if (a >= 1e5 || a < 1e-3) {
      const [m, e] = v.toExponential(digits - 2).split("e");
      return `${parseFloat(m)}e${parseInt(e, 10)}`;
    }
    return String(parseFloat(v.toPrecision(digits)));
  }

  function esc(s) {
    return String(s).replace(/[&<>"']/g, (c) => ({ "&": "&amp;", "<": "&lt;", ">": "&gt;", '"': "&quot;", "'": "&#39;" }[c]));
  }

  /* ---- slider positions (shared with the controls): log scale with 0 as its own first stop */
  const STEPS = 1000;
  function logLo(lo, hi) { return lo > 0 ? lo : hi * 1e-4; }
  function fromPos(k, lo, hi, scale) {
    if (scale !== "log") return lo + ((hi - lo) * k) / STEPS;
    if (lo > 0) return lo * Math.pow(hi / lo, k / STEPS);
    if (k <= 0) return lo;
    const a = logLo(lo, hi);
    return a * Math.pow(hi / a, (k - 1) / (STEPS - 1));
  }
  function toPos(v, lo, hi, scale) {
    if (scale !== "log") return Math.round(((v - lo) / (hi - lo)) * STEPS);
    if (lo > 0) return Math.round((Math.log(v / lo) / Math.log(hi / lo)) * STEPS);
    const a = logLo(lo, hi);
    if (v <= a / 2) return 0;
    if (v <= a) return 1;
    return Math.min(STEPS, 1 + Math.round((Math.log(v / a) / Math.log(hi / a)) * (STEPS - 1)));
  }

  /* ---- axes */
  function transform(axis, lo, hi) {
    if (axis.scale === "log") {
      const a = Math.log10(lo), b = Math.log10(hi);
      return (v) => (v > 0 ? (Math.log10(v) - a) / (b - a) : NaN);
    }
    if (axis.scale === "symlog") {
      const c = axis.c, f = (v) => Math.asinh(v / c), a = f(lo), b = f(hi);
      return (v) => (f(v) - a) / (b - a);
    }
    return (v) => (v - lo) / (hi - lo);
  }

  function niceStep(span, n) {
    const raw = span / n, p = Math.pow(10, Math.floor(Math.log10(raw))), r = raw / p;
    return (r < 1.5 ? 1 : r < 3 ? 2 : r < 7 ? 5 : 10) * p;
  }

  function ticks(axis, lo, hi) {
    if (axis.scale === "log") {
      const a = Math.floor(Math.log10(lo)), b = Math.ceil(Math.log10(hi));
      const every = Math.max(1, Math.ceil((b - a) / 6));
      const pick = (mults) => {
        const out = [];
        for (let e = a; e <= b; e += every) for (const m of mults) { const v = m * Math.pow(10, e); if (v >= lo * 0.999 && v <= hi * 1.001) out.push(v); }
        return out;
      };
      let out = pick([1]);
      if (out.length < 3) out = pick([1, 2, 5]);
      if (out.length < 3) out = ticks({ scale: "lin" }, lo, hi).filter((v) => v > 0);
      return out;
    }
    if (axis.scale === "symlog") {
      const out = [0];
      for (const s of [1, -1]) {
        const m = s > 0 ? hi : -lo;
        if (m <= axis.c) continue;
        const top = Math.floor(Math.log10(m)), bottom = Math.ceil(Math.log10(axis.c));
        const every = Math.max(1, Math.ceil((top - bottom + 1) / 3));
        for (let e = top; e >= bottom; e -= every) out.push(s * Math.pow(10, e));
      }
      return out;
    }
    const step = niceStep(hi - lo, 5), out = [];
    for (let v = Math.ceil(lo / step) * step; v <= hi + step * 1e-9; v += step) out.push(Math.abs(v) < step * 1e-9 ? 0 : v);
    return out;
  }

  function extent(arrays, scale) {
    let lo = Infinity, hi = -Infinity;
    for (const arr of arrays) for (const v of arr) {
      if (v === null || !Number.isFinite(v) || (scale === "log" && v <= 0)) continue;
      if (v < lo) lo = v; if (v > hi) hi = v;
    }
    if (!Number.isFinite(lo)) return scale === "log" ? [1, 10] : [0, 1];
    if (scale === "log") { if (hi <= lo * 1.0001) { lo /= 2; hi *= 2; } return [lo, hi]; }
    if (hi - lo <= Math.abs(hi) * 1e-9 + 1e-300) { const d = Math.abs(hi) * 0.1 || 1; return [lo - d, hi + d]; }
    const pad = (hi - lo) * 0.05; return [lo - pad, hi + pad];
  }

  function size(svg) { const vb = svg.viewBox.baseVal; return [vb.width, vb.height]; }

  /* line plot: opts = {x:{scale,label,lo,hi}, y:{scale,label,lo,hi,c}, series:[{x,y,color,width,dash,label}],
     bands:[[x0,x1]], vlines:[{x,color,label,dash}], hlines:[{y,color,dash,label}], title, note} */
  function line(svg, opts) {
    const [W, H] = size(svg), pw = W - M.l - M.r, ph = H - M.t - M.b;
    const xs = opts.series.map((s) => s.x), ys = opts.series.map((s) => s.y);
    let [x0, x1] = extent(xs, opts.x.scale); if (opts.x.scale === "log" || opts.x.tight) [x0, x1] = [Math.min(...xs.map((a) => a[0])), Math.max(...xs.map((a) => a[a.length - 1]))];
    if (opts.x.lo !== undefined) x0 = opts.x.lo; if (opts.x.hi !== undefined) x1 = opts.x.hi;
    const yax = Object.assign({}, opts.y);
    let [y0, y1] = extent(ys.concat((opts.hlines || []).map((h) => [h.y])), yax.scale);
    if (yax.scale === "symlog") {
      const m = Math.max(Math.abs(y0), Math.abs(y1)) || 1; yax.c = yax.c || m * 1e-3;
      const lo = Math.min(y0, 0), hi = Math.max(y1, 0); const pad = 0.05 * (Math.asinh(hi / yax.c) - Math.asinh(lo / yax.c));
      y0 = yax.c * Math.sinh(Math.asinh(lo / yax.c) - pad); y1 = yax.c * Math.sinh(Math.asinh(hi / yax.c) + pad);
    }
    if (yax.lo !== undefined) y0 = yax.lo; if (yax.hi !== undefined) y1 = yax.hi;
    const fx = transform(opts.x, x0, x1), fy = transform(yax, y0, y1);
    const X = (v) => M.l + fx(v) * pw, Y = (v) => M.t + (1 - fy(v)) * ph;
    const parts = [];
    parts.push(`<defs><clipPath id="${svg.id}-clip"><rect x="${M.l}" y="${M.t}" width="${pw}" height="${ph}"/></clipPath></defs>`);
    for (const [a, b] of opts.bands || []) {
      const xa = Math.max(M.l, a > 0 || opts.x.scale !== "log" ? X(a) : M.l), xb = Math.min(M.l + pw, b === null ? M.l + pw : X(b));
      if (xb > xa) parts.push(`<rect class="band" x="${xa.toFixed(1)}" y="${M.t}" width="${(xb - xa).toFixed(1)}" height="${ph}"/>`);
    }
    for (const t of ticks(opts.x, x0, x1)) {
      const x = X(t); if (!(x >= M.l - 0.5 && x <= M.l + pw + 0.5)) continue;
      parts.push(`<line class="grid" x1="${x.toFixed(1)}" x2="${x.toFixed(1)}" y1="${M.t}" y2="${M.t + ph}"/><text class="tick" x="${x.toFixed(1)}" y="${M.t + ph + 13}" text-anchor="middle">${fmt(t, 3)}</text>`);
    }
    for (const t of ticks(yax, y0, y1)) {
      const y = Y(t); if (!(y >= M.t - 0.5 && y <= M.t + ph + 0.5)) continue;
      parts.push(`<line class="grid" x1="${M.l}" x2="${M.l + pw}" y1="${y.toFixed(1)}" y2="${y.toFixed(1)}"/><text class="tick" x="${M.l - 4}" y="${(y + 3).toFixed(1)}" text-anchor="end">${fmt(t, 3)}</text>`);
    }
    parts.push(`<rect class="axis" x="${M.l}" y="${M.t}" width="${pw}" height="${ph}"/>`);
    const body = [];
    for (const h of opts.hlines || []) {
      const y = Y(h.y); if (y >= M.t && y <= M.t + ph) body.push(`<line x1="${M.l}" x2="${M.l + pw}" y1="${y.toFixed(1)}" y2="${y.toFixed(1)}" stroke="${h.color || "#8c959f"}" stroke-dasharray="${h.dash || "4 3"}"/>`);
    }
    for (const v of opts.vlines || []) {
      const x = X(v.x); if (x >= M.l && x <= M.l + pw) body.push(`<line x1="${x.toFixed(1)}" x2="${x.toFixed(1)}" y1="${M.t}" y2="${M.t + ph}" stroke="${v.color || "#1f2328"}" stroke-dasharray="${v.dash || "3 3"}"/>`);
    }
    for (const s of opts.series) {
      let d = "", pen = false;
      for (let i = 0; i < s.x.length; i++) {
        const xv = s.x[i], yv = s.y[i];
        const px = X(xv), py = Y(yv);
        if (yv === null || !Number.isFinite(px) || !Number.isFinite(py)) { pen = false; continue; }
        const cy = Math.max(M.t - 1000, Math.min(M.t + ph + 1000, py));
        d += (pen ? "L" : "M") + px.toFixed(1) + " " + cy.toFixed(1);
        pen = true;
      }
      body.push(`<path d="${d}" fill="none" stroke="${s.color || "#0969da"}" stroke-width="${s.width || 1.6}"${s.dash ? ` stroke-dasharray="${s.dash}"` : ""} data-series="${esc(s.label || "")}"/>`);
    }
    parts.push(`<g clip-path="url(#${svg.id}-clip)">${body.join("")}</g>`);
    const labeled = opts.series.filter((s) => s.label);
    labeled.forEach((s, i) => {
      const x = M.l + pw - 30, y = M.t + 12 + i * 13;
      parts.push(`<rect x="${x - 48}" y="${y - 10}" width="78" height="13" fill="#ffffffcc"/><line x1="${x - 44}" x2="${x - 30}" y1="${y - 3}" y2="${y - 3}" stroke="${s.color || "#0969da"}" stroke-width="2"${s.dash ? ` stroke-dasharray="${s.dash}"` : ""}/><text class="legend" x="${x - 27}" y="${y}">${esc(s.label)}</text>`);
    });
    if (opts.title) parts.push(`<text class="title" x="${M.l}" y="13">${esc(opts.title)}</text>`);
    if (opts.x.label) parts.push(`<text x="${M.l + pw / 2}" y="${H - 4}" text-anchor="middle">${esc(opts.x.label)}</text>`);
    if (opts.y.label) parts.push(`<text transform="translate(12 ${M.t + ph / 2}) rotate(-90)" text-anchor="middle">${esc(opts.y.label)}</text>`);
    svg.innerHTML = parts.join("");
  }

  /* position of value v on a grid of values (index space, fractional) */
  function gridPos(grid, v) {
    const n = grid.length;
    if (v <= grid[0]) return 0;
    if (v >= grid[n - 1]) return n - 1;
    let i = 0; while (i < n - 2 && grid[i + 1] < v) i++;
    const a = grid[i], b = grid[i + 1];
    const f = a > 0 ? Math.log(v / a) / Math.log(b / a) : (v - a) / (b - a);
    return i + Math.max(0, Math.min(1, f));
  }

  function gridTicks(grid, scale) {
    const lo = grid[0], hi = grid[grid.length - 1], out = [];
    if (scale === "log") {
      if (lo === 0) out.push(0);
      const start = lo > 0 ? lo : grid[1];
      for (const t of ticks({ scale: "log" }, start, hi)) out.push(t);
      return out;
    }
    return ticks({ scale: "lin" }, lo, hi);
  }

  /* drop ticks closer than 8 % of the axis to the previous one (0 next to the first log decade) */
  function spaced(tks, where) {
    const out = []; let last = -1;
    for (const t of tks) { const p = where(t); if (last < 0 || p - last >= 0.08) { out.push(t); last = p; } }
    return out;
  }

  /* 2-D passive region: raster of exact verdicts, current point marked */
  function region(svg, data, cur) {
    const [W, H] = size(svg), pw = W - M.l - M.r - 90, ph = H - M.t - M.b;
    const nx = data.xs.length, ny = data.ys.length;
    const canvas = document.createElement("canvas"); canvas.width = nx; canvas.height = ny;
    const ctx = canvas.getContext("2d"), img = ctx.createImageData(nx, ny);
    for (let j = 0; j < ny; j++) {
      const row = data.passive[j];
      for (let i = 0; i < nx; i++) {
        const k = 4 * ((ny - 1 - j) * nx + i), ok = row.charCodeAt(i) === 49;
        img.data[k] = ok ? 74 : 255; img.data[k + 1] = ok ? 194 : 129; img.data[k + 2] = ok ? 107 : 130; img.data[k + 3] = 255;
      }
    }
    ctx.putImageData(img, 0, 0);
    const X = (p) => M.l + ((p + 0.5) / nx) * pw, Y = (p) => M.t + (1 - (p + 0.5) / ny) * ph;
    const parts = [`<image href="${canvas.toDataURL()}" x="${M.l}" y="${M.t}" width="${pw}" height="${ph}" preserveAspectRatio="none" class="raster"/>`];
    for (const t of spaced(gridTicks(data.xs, data.x_scale), (t) => gridPos(data.xs, t) / nx)) {
      const x = X(gridPos(data.xs, t));
      parts.push(`<line class="axis" x1="${x.toFixed(1)}" x2="${x.toFixed(1)}" y1="${M.t + ph}" y2="${M.t + ph + 4}"/><text class="tick" x="${x.toFixed(1)}" y="${M.t + ph + 14}" text-anchor="middle">${fmt(t, 3)}</text>`);
    }
    for (const t of spaced(gridTicks(data.ys, data.y_scale), (t) => gridPos(data.ys, t) / ny)) {
      const y = Y(gridPos(data.ys, t));
      parts.push(`<line class="axis" x1="${M.l - 4}" x2="${M.l}" y1="${y.toFixed(1)}" y2="${y.toFixed(1)}"/><text class="tick" x="${M.l - 6}" y="${(y + 3).toFixed(1)}" text-anchor="end">${fmt(t, 3)}</text>`);
    }
    parts.push(`<rect class="axis" x="${M.l}" y="${M.t}" width="${pw}" height="${ph}"/>`);
    if (cur) {
      const cx = X(gridPos(data.xs, cur[0])), cy = Y(gridPos(data.ys, cur[1]));
      parts.push(`<circle id="region-point" cx="${cx.toFixed(1)}" cy="${cy.toFixed(1)}" r="6" fill="none" class="cur"/><circle cx="${cx.toFixed(1)}" cy="${cy.toFixed(1)}" r="2" fill="#1f2328"/>`);
    }
    const lx = M.l + pw + 12;
    parts.push(`<rect x="${lx}" y="${M.t}" width="12" height="12" class="ok"/><text x="${lx + 16}" y="${M.t + 10}">passive</text>`);
    parts.push(`<rect x="${lx}" y="${M.t + 18}" width="12" height="12" class="bad"/><text x="${lx + 16}" y="${M.t + 28}">not passive</text>`);
    parts.push(`<circle cx="${lx + 6}" cy="${M.t + 43}" r="5" fill="none" class="cur"/><text x="${lx + 16}" y="${M.t + 47}">current</text>`);
    parts.push(`<text x="${M.l + pw / 2}" y="${H - 4}" text-anchor="middle">${esc(data.x)}</text>`);
    parts.push(`<text transform="translate(12 ${M.t + ph / 2}) rotate(-90)" text-anchor="middle">${esc(data.y)}</text>`);
    svg.innerHTML = parts.join("");
  }

  /* exact passive set of one parameter on its slider axis, the current value marked */
  function interval(svg, data, value) {
    const [W] = size(svg), pw = W - 24, x0 = 12, y = 30, h = 26;
    const X = (v) => x0 + (toPos(Math.min(Math.max(v, data.lo), data.hi), data.lo, data.hi, data.scale) / STEPS) * pw;
    const parts = [`<rect x="${x0}" y="${y}" width="${pw}" height="${h}" class="bad"/>`];
    for (const [a, b] of data.intervals) {
      const xa = X(a), xb = X(b);
      parts.push(`<rect x="${xa.toFixed(1)}" y="${y}" width="${Math.max(2, xb - xa).toFixed(1)}" height="${h}" class="ok" data-interval="${a},${b}"/>`);
    }
    const tks = data.scale === "log" ? [data.lo].concat(ticks({ scale: "log" }, data.lo > 0 ? data.lo : data.hi * 1e-4, data.hi)) : ticks({ scale: "lin" }, data.lo, data.hi);
    for (const t of spaced(tks, (t) => (X(t) - x0) / pw)) {
      const x = X(t);
      parts.push(`<line class="axis" x1="${x.toFixed(1)}" x2="${x.toFixed(1)}" y1="${y + h}" y2="${y + h + 4}"/><text class="tick" x="${x.toFixed(1)}" y="${y + h + 15}" text-anchor="middle">${fmt(t, 3)}</text>`);
    }
    for (const [a, b] of data.intervals) {
      for (const e of [a, b]) if (e > data.lo && e < data.hi) {
        const x = X(e); parts.push(`<text class="tick" x="${x.toFixed(1)}" y="${y - 4}" text-anchor="middle">${fmt(e, 6)}</text>`);
      }
    }
    parts.push(`<rect class="axis" x="${x0}" y="${y}" width="${pw}" height="${h}"/>`);
    const xv = X(value);
    parts.push(`<path id="interval-marker" d="M${xv.toFixed(1)} ${y - 2}V${y + h + 2}" class="cur"/><path d="M${(xv - 5).toFixed(1)} ${y + h + 22}L${xv.toFixed(1)} ${y + h + 16}L${(xv + 5).toFixed(1)} ${y + h + 22}Z" fill="#1f2328"/>`);
    parts.push(`<text x="${x0}" y="13" class="title">${esc(data.param)} = ${fmt(value, 6)}</text>`);
    svg.innerHTML = parts.join("");
  }

  return { fmt, esc, line, region, interval, fromPos, toPos, STEPS, NS };
})();
