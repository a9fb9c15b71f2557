/* seapass explore: controls, requests and panels.  The server validates and computes everything;
 * this script keeps the view in the URL, sends one request per panel (at most one in flight per
 * panel, the newest view wins) and draws the answers. */
"use strict";

(() => {
  const $ = (sel) => document.querySelector(sel);
  const fmt = Plots.fmt, esc = Plots.esc;
  let KINDS = [], RESOLUTIONS = [24], CHUNK = 16, PRESETS = [];
  let S = null;            // the current validated view (as the server normalized it)
  let version = 0;         // one number per distinct view
  const started = {};      // version -> time of the event that made it
  const shown = {}, inflight = {}, data = {};
  let recorded = 0, fineFor = 0;
  const timings = [];      // {version, ms, at, kinds}: the page's own clock, for the benchmark
  const releases = [];     // {version, t}: slider releases (the view current at the release)
  const kindTimes = {};    // version -> {panel kind: ms after the change}

  /* ------------------------------------------------------------------ conditions (non-model controls) */
  const CONDITIONS = [
    { key: "load_mass", label: "load", unit: "kg", lo: 0.1, hi: 1000, scale: "log" },
    { key: "step", label: "step", unit: "m", lo: 0.01, hi: 10, scale: "log" },
    { key: "horizon", label: "horizon", unit: "s", lo: 0.1, hi: 100, scale: "log" },
    { key: "period", label: "period", unit: "s", lo: 1e-4, hi: 0.1, scale: "log", optional: true },
    { key: "delay", label: "delay", unit: "smp", lo: 0, hi: 10, scale: "lin", integer: true },
    { key: "velocity_filter", label: "filter", unit: "Hz", lo: 1, hi: 1e4, scale: "log", optional: true },
    { key: "delay_time", label: "latency", unit: "s", lo: 1e-5, hi: 0.1, scale: "log", optional: true },
  ];

  function round4(v) { return v === 0 ? 0 : parseFloat(v.toPrecision(4)); }

  async function post(url, body) {
    const r = await fetch(url, { method: "POST", headers: { "Content-Type": "application/json" }, body: JSON.stringify(body) });
    return r.json();
  }

  /* ------------------------------------------------------------------ URL <-> view */
  function encode(st) {
    const q = new URLSearchParams();
    q.set("name", st.name); if (st.title) q.set("title", st.title);
    for (const k of ["D1", "D2", "CA", "CL"]) if (st.model[k] && st.model[k] !== "0") q.set(k, st.model[k]);
    for (const [k, v] of Object.entries(st.values)) q.set("p." + k, v);
    for (const [k, r] of Object.entries(st.ranges)) q.set("r." + k, r.join(","));
    q.set("gain", st.gain); q.set("region", st.region.join(","));
    for (const c of CONDITIONS) q.set(c.key, st[c.key] === null || st[c.key] === undefined ? "off" : st[c.key]);
    for (const [k, r] of Object.entries(st.uncertainty || {})) q.set("u." + k, r.join(","));
    return q.toString();
  }

  function decode(hash) {
    const q = new URLSearchParams(hash.replace(/^#/, ""));
    if (!q.has("D1") && !q.has("D2")) return null;
    const st = { model: {}, values: {}, ranges: {}, uncertainty: {} };
    for (const [k, v] of q) {
      if (["D1", "D2", "CA", "CL"].includes(k)) st.model[k] = v;
      else if (k.startsWith("p.")) st.values[k.slice(2)] = v;
      else if (k.startsWith("r.")) st.ranges[k.slice(2)] = v.split(",");
      else if (k.startsWith("u.")) st.uncertainty[k.slice(2)] = v.split(",").map(Number);
      else if (k === "region") st.region = v.split(",");
      else st[k] = v;
    }
    for (const c of CONDITIONS) if (st[c.key] === "off") st[c.key] = null;
    return st;
  }

  /* ------------------------------------------------------------------ errors next to their boxes */
  function showErrors(errors) {
    document.querySelectorAll("[data-err]").forEach((el) => { el.textContent = errors[el.dataset.err] || ""; });
    document.querySelectorAll("[data-field]").forEach((el) => { el.classList.toggle("invalid", !!errors[el.dataset.field]); });
    const extra = Object.keys(errors).filter((k) => !document.querySelector(`[data-err="${k}"]`));
    if (extra.length) $("[data-err=model]").textContent = extra.map((k) => `${k}: ${errors[k]}`).join("; ");
  }

  /* ------------------------------------------------------------------ controls */
  function sliderRow(opts) {
    // opts: {id, name, label, unit, lo, hi, scale, value, radio, field, onSlide, onText, optional, integer}
    const row = document.createElement("div");
    row.className = "param"; row.dataset.name = opts.name;
    row.innerHTML =
      (opts.radio ? `<input type="radio" name="gain" value="${esc(opts.name)}" title="show the passive interval of ${esc(opts.name)}">` : "<span></span>") +
      `<span class="name" title="${esc(opts.label)}">${esc(opts.label)}${opts.unit ? ` <small>${esc(opts.unit)}</small>` : ""}</span>` +
      `<input type="range" id="slider-${esc(opts.id)}" min="0" max="${Plots.STEPS}" step="1" aria-label="${esc(opts.label)}">` +
      `<input type="text" id="box-${esc(opts.id)}" data-field="${esc(opts.field)}" aria-label="${esc(opts.label)} value"${opts.optional ? ' placeholder="off"' : ""}>` +
      `<div class="range"><span class="lo"></span><span class="hi"></span></div>` +
      `<div class="err" data-err="${esc(opts.field)}"></div>`;
    const slider = row.querySelector("input[type=range]"), box = row.querySelector("input[type=text]");
    row._opts = opts;
    slider.addEventListener("input", (e) => {
      const o = row._opts;
      let v = Plots.fromPos(+slider.value, o.lo, o.hi, o.scale);
      v = o.integer ? Math.round(v) : round4(v);
      box.value = fmt(v, 6); box.classList.remove("invalid");
      opts.onSlide(v, e.timeStamp);
    });
    slider.addEventListener("change", (e) => { releases.push({ version, t: e.timeStamp }); });
    box.addEventListener("change", (e) => opts.onText(box.value, e.timeStamp));
    box.addEventListener("keydown", (e) => { if (e.key === "Enter") box.dispatchEvent(new Event("change")); });
    return row;
  }

  function setRow(row, value, lo, hi, scale) {
    Object.assign(row._opts, { lo, hi, scale });
    const slider = row.querySelector("input[type=range]"), box = row.querySelector("input[type=text]");
    if (value === null || value === undefined) { slider.value = 0; slider.disabled = false; if (document.activeElement !== box) box.value = ""; }
    else {
      slider.value = Plots.toPos(Math.min(Math.max(value, lo), hi), lo, hi, scale);
      if (document.activeElement !== box) box.value = fmt(value, 6);
    }
    row.querySelector(".lo").textContent = fmt(lo, 3);
    row.querySelector(".hi").textContent = fmt(hi, 3) + (scale === "log" ? " (log)" : "");
  }

  function buildParams(st) {
    const host = $("#params");
    const names = Object.keys(st.values);
    const have = [...host.children].map((r) => r.dataset.name);
    if (have.join() !== names.join()) {
      host.innerHTML = "";
      for (const n of names) {
        host.appendChild(sliderRow({
          id: n, name: n, label: n, unit: "", field: "values." + n, radio: true,
          lo: st.ranges[n][0], hi: st.ranges[n][1], scale: st.scales[n],
          onSlide: (v, t) => { S = Object.assign({}, S, { values: Object.assign({}, S.values, { [n]: v }) }); quick(t); },
          onText: (text, t) => { const raw = clone(S); raw.values[n] = text; validate(raw, t); },
        }));
      }
      host.querySelectorAll("input[type=radio]").forEach((r) => r.addEventListener("change", (e) => {
        S = Object.assign({}, S, { gain: r.value }); validate(clone(S), e.timeStamp);
      }));
    }
    for (const row of host.children) {
      const n = row.dataset.name;
      setRow(row, st.values[n], st.ranges[n][0], st.ranges[n][1], st.scales[n]);
      row.querySelector("input[type=radio]").checked = n === st.gain;
    }
    for (const id of ["region-x", "region-y"]) {
      const sel = $("#" + id), want = st.region[id === "region-x" ? 0 : 1];
      if ([...sel.options].map((o) => o.value).join() !== names.join()) sel.innerHTML = names.map((n) => `<option>${esc(n)}</option>`).join("");
      sel.value = want;
    }
    $("#new-params").textContent = st.new_parameters.length ? `new parameter(s): ${st.new_parameters.join(", ")}; set their values below` : "";
  }

  function buildConditions() {
    const host = $("#conditions");
    for (const c of CONDITIONS) {
      host.appendChild(sliderRow({
        id: c.key, name: c.key, label: c.label, unit: c.unit, field: c.key, lo: c.lo, hi: c.hi, scale: c.scale,
        optional: c.optional, integer: c.integer,
        onSlide: (v, t) => { S = Object.assign({}, S, { [c.key]: v }); quick(t); },
        onText: (text, t) => { const raw = clone(S); raw[c.key] = text.trim() === "" ? null : text; validate(raw, t); },
      }));
    }
  }

  function syncControls(st) {
    for (const k of ["D1", "D2", "CA", "CL"]) {
      const el = $("#model-" + k);
      if (document.activeElement !== el || el.value.trim() === "") el.value = st.model[k];
    }
    buildParams(st);
    for (const row of $("#conditions").children) {
      const c = CONDITIONS.find((x) => x.key === row.dataset.name), v = st[c.key];
      const lo = v !== null && v < c.lo ? v : c.lo, hi = v !== null && v > c.hi ? v : c.hi;
      setRow(row, v, lo, hi, c.scale === "log" && lo <= 0 ? "lin" : c.scale);
    }
    const hz = st.period ? ` (${fmt(1 / st.period, 4)} Hz)` : "";
    $("#verdict-sampled .what").textContent = st.period ? `sampled at T = ${fmt(st.period, 4)} s${hz}` + (st.delay ? `, delay ${st.delay}` : "") + (st.velocity_filter ? `, ${fmt(st.velocity_filter, 4)} Hz velocity filter` : "") : "sampled";
  }

  function clone(x) { return JSON.parse(JSON.stringify(x)); }

  /* ------------------------------------------------------------------ the change pipeline */
  function setStatus(text, cls) { const el = $("#status"); el.textContent = text; el.className = "status " + cls; }

  function newVersion(t) {
    version += 1; started[version] = t === undefined ? performance.now() : t;
    document.body.dataset.busy = "1";
    setStatus("updating…", "busy");
    return version;
  }

  // a slider move: the value is valid by construction, so the panels start at once
  function quick(t) {
    newVersion(t);
    dispatch();
    history.replaceState(null, "", "#" + encode(S));
    drawMarkers();
  }

  // anything typed or picked: the server validates the whole view first
  async function validate(raw, t) {
    const v = newVersion(t);
    let chk;
    try { chk = await post("/api/state", raw); } catch (e) { setStatus("server unreachable", "error"); return; }
    if (v !== version) return;
    showErrors(chk.errors || {});
    if (!chk.ok) {
      setStatus("fix the marked field", "error");
      document.querySelectorAll(".panel").forEach((p) => p.classList.add("stale"));
      document.body.dataset.busy = "0";
      return;
    }
    S = chk.state;
    syncControls(S);
    history.replaceState(null, "", "#" + encode(S));
    dispatch();
  }

  // one streamed request for every panel that is not busy; a busy one is asked again when it answers
  function dispatch() {
    const kinds = KINDS.filter((k) => !inflight[k] && shown[k] !== version);
    if (!kinds.length) return;
    const v = version, st = S;
    kinds.forEach((k) => { inflight[k] = true; });
    const answered = new Set();
    const onLine = (r) => {
      const kind = r.kind;
      answered.add(kind); inflight[kind] = false;
      render(kind, r, st);
      shown[kind] = v;
      if (!kindTimes[v]) kindTimes[v] = {};
      kindTimes[v][kind] = performance.now() - started[v];
      if (v !== version) dispatch(); else finish();
    };
    stream("/api/panels", { state: st, kinds }, onLine).catch(() => setStatus("server unreachable", "error")).finally(() => {
      kinds.forEach((k) => { if (!answered.has(k)) inflight[k] = false; });
      if (v !== version) dispatch();
    });
  }

  async function stream(url, body, onLine) {
    const r = await fetch(url, { method: "POST", headers: { "Content-Type": "application/json" }, body: JSON.stringify(body) });
    if (!r.ok || !r.body) { const j = await r.json(); throw new Error(j.error || r.statusText); }
    const reader = r.body.getReader(), dec = new TextDecoder();
    let buf = "";
    for (;;) {
      const { value, done } = await reader.read();
      if (value) buf += dec.decode(value, { stream: true });
      let i;
      while ((i = buf.indexOf("\n")) >= 0) { const line = buf.slice(0, i); buf = buf.slice(i + 1); if (line.trim()) onLine(JSON.parse(line)); }
      if (done) return;
    }
  }

  function finish() {
    const v = version;
    if (recorded === v || !KINDS.every((k) => shown[k] === v)) return;
    recorded = v;
    requestAnimationFrame(() => {
      const at = performance.now(), ms = at - started[v];
      timings.push({ version: v, ms, at, kinds: kindTimes[v] });
      if (v === version) {
        document.body.dataset.busy = "0"; document.body.dataset.version = String(v);
        setStatus(`up to date · ${ms.toFixed(0)} ms`, "idle");
        refine(v);
      }
    });
  }

  // the 2-D region refines once the view has been still for a moment, a few rows per request,
  // and stops as soon as the view changes, so it never delays the panels of the next change
  const REFINE_AFTER_MS = 300;
  function refine(v) {
    if (fineFor === v) return;
    fineFor = v;
    setTimeout(async () => {
      for (const res of RESOLUTIONS.slice(1)) {
        const st = S, rows = [];
        let head = null;
        for (let r0 = 0; r0 < res; r0 += CHUNK) {
          if (v !== version) return;
          const r = await post("/api/panel/region", { state: st, resolution: res, rows: [r0, Math.min(res, r0 + CHUNK)] });
          if (v !== version) return;
          if (!r.ok) { panelError("region", r); return; }
          head = r.data; rows.push(...r.data.passive);
        }
        render("region", { ok: true, data: Object.assign({}, head, { passive: rows, rows: [0, res] }) }, st);
      }
    }, REFINE_AFTER_MS);
  }

  /* ------------------------------------------------------------------ panels */
  function panelError(kind, r) {
    const el = document.querySelector(`[data-panel-err="${kind}"]`);
    if (el) el.textContent = r.ok ? "" : r.error;
    const panel = { verdict: "verdict", sampled: "verdict", robust: "verdict", interval: "interval", region: "region", frequency: "frequency", step: "step", witness: "witness", twoport: "twoport", delay: "verdict" }[kind];
    $("#panel-" + panel).classList.toggle("stale", !r.ok && kind !== "sampled" && kind !== "delay" && kind !== "robust");
  }

  function setVerdict(el, cls, v, why) {
    el.className = "verdict " + cls; el.querySelector(".v").textContent = v; el.querySelector(".why").textContent = why;
  }

  const RENDER = {
    verdict(d) {
      setVerdict($("#verdict-continuous"), d.passive ? "passive" : "notpassive", d.status,
        d.passive ? "positive real: passive with every passive environment" : `${d.detail}`);
    },
    sampled(d) {
      if (!d.analysed) { setVerdict($("#verdict-sampled"), "off", "not analysed", d.detail); return; }
      setVerdict($("#verdict-sampled"), d.passive ? "passive" : "notpassive", d.status, d.passive ? "passive at this sampling period" : d.detail);
    },
    robust(d) {  // the box verdict: passive for the whole box, a worst plant, or undecided
      if (!d.analysed) { setVerdict($("#verdict-robust"), "off", "no box", d.detail); return; }
      const box = Object.entries(d.box).map(([k, [lo, hi]]) => `${k} ∈ [${lo}, ${hi}]`).join(", ");
      const worst = d.worst ? "worst plant: " + Object.entries(d.worst.values).map(([k, v]) => `${k} = ${fmt(v, 6)}`).join(", ") + (d.worst.frequency ? ` (Re Z < 0 at ω = ${fmt(d.worst.frequency, 4)} rad/s)` : "") : "";
      setVerdict($("#verdict-robust"), d.passive ? "passive" : (d.status === "undecided" ? "off" : "notpassive"), d.status,
        d.passive ? `passive for the whole box ${box}` : (worst || d.detail));
    },
    interval(d) {
      data.interval = d;
      $("#interval-param").textContent = d.param;
      Plots.interval($("#plot-interval"), d, S.values[d.param]);
      // the server rounds the ends inward (d.shown): a printed end is itself passive
      const ivs = d.intervals.map(([a, b], i) => (a === b ? `{${d.shown[i][0]}}` : `[${d.shown[i][0]}, ${d.shown[i][1]}]`));
      const inside = d.intervals.some(([a, b]) => a <= S.values[d.param] && S.values[d.param] <= b);
      $("#interval-text").innerHTML = ivs.length
        ? `passive for <b>${esc(d.param)} ∈ ${ivs.join(" ∪ ")}</b> within [${fmt(d.lo, 4)}, ${fmt(d.hi, 4)}], the others fixed (exact). Current value ${inside ? "inside" : "<b>outside</b>"}.`
        : `<b>no value</b> of ${esc(d.param)} in [${fmt(d.lo, 4)}, ${fmt(d.hi, 4)}] is passive, the others fixed (exact).`;
    },
    region(d) {
      data.region = d;
      $("#region-title").textContent = `${d.y} against ${d.x}`;
      Plots.region($("#plot-region"), d, [S.values[d.x], S.values[d.y]]);
      $("#region-text").textContent = `${d.resolution}×${d.resolution} grid, every point decided exactly (batch engine${d.exact_fallbacks ? `, ${d.exact_fallbacks} by rational arithmetic` : ""}); other parameters fixed.` + (d.undefined ? ` ${d.undefined} points undefined (zero denominator).` : "");
    },
    frequency(d) {
      const w = d.omega;
      Plots.line($("#plot-magnitude"), { title: "|F_L/X_L| [N/m]", x: { scale: "log", label: "ω [rad/s]" }, y: { scale: "log" }, series: [{ x: w, y: d.magnitude }], bands: d.bands });
      Plots.line($("#plot-phase"), { title: "phase [deg]", x: { scale: "log", label: "ω [rad/s]" }, y: { scale: "lin" }, series: [{ x: w, y: d.phase, color: "#8250df" }], bands: d.bands });
      Plots.line($("#plot-rez"), { title: "Re Z(jω) [N·s/m]", x: { scale: "log", label: "ω [rad/s]" }, y: { scale: "symlog" }, series: [{ x: w, y: d.re_z, color: "#1a7f37" }], bands: d.bands, hlines: [{ y: 0, color: "#cf222e" }] });
      $("#frequency-text").innerHTML = d.bands.length
        ? `Re Z(jω) &lt; 0 (shaded, exact) for ω ∈ ${d.bands.map(([a, b]) => `(${fmt(a, 5)}, ${b === null ? "∞" : fmt(b, 5)})`).join(" ∪ ")} rad/s.`
        : "Re Z(jω) ≥ 0 at every frequency (exact).";
      $("#frequency-text").innerHTML += ` Static stiffness ${d.static === null ? "∞" : fmt(d.static, 4)} N/m, high-frequency ${d.high_frequency === null ? "∞" : fmt(d.high_frequency, 4)} N/m.`;
    },
    step(d) {
      $("#step-title").textContent = `(m_L = ${fmt(d.load_mass, 4)} kg, step ${fmt(d.step, 4)} m)`;
      const ref = d.t.map(() => d.target);
      Plots.line($("#plot-step"), { title: "position [m]", x: { scale: "lin", label: "t [s]", tight: true }, y: { scale: "lin" },
        series: [{ x: d.t, y: ref, color: "#8c959f", dash: "5 4", label: "reference", width: 1.2 }, { x: d.t, y: d.x_A, color: "#bf8700", label: "x_A", width: 1.2 }, { x: d.t, y: d.x_L, color: "#0969da", label: "x_L" }],
        vlines: d.settling_time !== null ? [{ x: d.settling_time, color: "#1a7f37", dash: "2 2" }] : [] });
      Plots.line($("#plot-force"), { title: "actuator force f_A [N]", x: { scale: "lin", label: "t [s]", tight: true }, y: { scale: "lin" }, series: [{ x: d.t, y: d.f_A, color: "#cf222e" }] });
      const st = d.status === "settled" ? `settling time (2 %) <b>${fmt(d.settling_time, 4)} s</b>` : `<b>${esc(d.status)}</b> within ${fmt(d.t[d.t.length - 1], 3)} s`;
      $("#step-text").innerHTML = `${st} · overshoot <b>${d.overshoot === null ? "—" : fmt(100 * d.overshoot, 3) + " %"}</b> · peak force <b>${fmt(d.peak_force, 4)} N</b>` + (d.final_error !== null ? ` · final error ${fmt(d.final_error, 3)} m` : "");
    },
    witness(d) {
      const svg = $("#plot-witness");
      if (d.passive) {
        svg.innerHTML = `<text x="240" y="125" text-anchor="middle" class="tick">passive: no passive environment can destabilize it</text>`;
        $("#witness-text").textContent = d.detail; return;
      }
      if (!d.found) { svg.innerHTML = ""; $("#witness-text").textContent = d.detail; return; }
      const e = d.environment;
      if (d.simulation) {
        Plots.line(svg, { title: `coupled response (${d.simulation.output})`, x: { scale: "lin", label: "t [s]", tight: true }, y: { scale: "lin" }, series: [{ x: d.simulation.t, y: d.simulation.y, color: "#cf222e" }] });
      } else svg.innerHTML = "";
      $("#witness-text").innerHTML = `The passive environment <b>m_e = ${fmt(e.mass, 4)} kg, b_e = ${fmt(e.damping, 4)} N·s/m, k_e = ${fmt(e.stiffness, 4)} N/m</b> makes the coupled system unstable: a pole at Re s = <b>${fmt(d.growth_rate, 4)} 1/s</b> (verified exactly${d.omega ? `; tuned at ω0 = ${fmt(d.omega, 4)} rad/s` : ""}).` +
        (d.simulation ? ` The response grows ×${fmt(d.simulation.growth_factor, 3)} from the first to the last quarter.` : "");
    },
    delay(d) {
      // tau* from the server, ends rounded outward (d.shown): every delay up to the lower end is certified passive;
      // with a loop latency (d.latency) the verdict is the server's for every delay up to it
      const el = $("#verdict-delay");
      if (!d.analysed) { setVerdict(el, "off", "not analysed", d.detail); return; }
      const at = d.latency ? `; latency ${fmt(d.latency, 4)} s: ${d.latency_outcome === "passive" ? "every delay up to it certified passive" : d.latency_outcome === "not_passive" ? "not passive" : "undecided"}` : "";
      const show = (cls, value, why) => setVerdict(el, d.latency && cls === "passive" && d.latency_outcome !== "passive" ? (d.latency_outcome === "not_passive" ? "notpassive" : "off") : cls, value, why + at);
      if (!d.passive_at_zero) { show("notpassive", "none", "not passive even without delay"); return; }
      if (d.delay_independent) { show("passive", "∞", "passive for every delay (exact)"); return; }
      if (d.outcome !== "passive" || d.shown === null) {
        show("off", "undecided", (d.shown ? `τ* ≤ ${d.shown[1]} s; ` : "") + d.detail); return;
      }
      if (d.tau_star[1] === 0) { show("notpassive", "0", "τ* = 0 (exact): every delay > 0 breaks passivity (" + d.loss + ")"); return; }
      const where = d.loss === "interior" ? `at ω = ${fmt(d.frequency, 5)} rad/s` : d.loss === "low_frequency" ? "as ω → 0" : "at arbitrarily high frequencies";
      show("passive", `${d.shown[0]} s`, `τ* ∈ [${d.shown[0]}, ${d.shown[1]}] s; lost ${where} (${d.loss})`);
    },
    twoport(d) {
      const words = { passive: ["passive", "absolutely stable"], not_passive: ["notpassive", "not absolutely stable"], undecided: ["off", "undecided"] }[d.outcome];
      setVerdict($("#verdict-absolute"), words[0], words[1],
        d.outcome === "passive" ? "stable with every passive person and every passive virtual environment"
          : d.outcome === "undecided" ? "the exact test could not decide (never shown as stable)"
            : "fails: " + d.failing.map((c) => c.name).join(", "));
      const eta = d.eta_min === null ? (d.eta_kind === "undefined" ? "undefined" : "−∞") : fmt(d.eta_min, 5);
      setVerdict($("#verdict-eta"), "eta", eta, d.eta_text);
      const hasEta = d.eta.some((v) => v !== null);
      if (hasEta) {
        Plots.line($("#plot-eta"), { title: "η(ω)", x: { scale: "log", label: "ω [rad/s]" }, y: { scale: "lin", lo: d.eta_range[0], hi: d.eta_range[1] },
          series: [{ x: d.omega, y: d.eta, color: "#0969da" }], bands: d.bands, hlines: [{ y: 1, color: "#cf222e", dash: "5 4" }] });
      } else $("#plot-eta").innerHTML = `<text x="280" y="115" text-anchor="middle" class="tick">η does not exist: p12 p21 = 0 (no coupling between the ports)</text>`;
      const failing = d.failing.filter((c) => c.bands.length).map((c) => `${esc(c.name)} for ω ∈ ${c.bands.map(([a, b]) => `(${fmt(a, 5)}, ${b === null ? "∞" : fmt(b, 5)})`).join(" ∪ ")}`);
      $("#twoport-text").innerHTML = (failing.length ? `Fails (shaded, exact): ${failing.join("; ")} rad/s. ` : "") +
        `${d.reciprocal ? "Reciprocal" : "Not reciprocal"} (z12 = z21: ${d.reciprocal ? "yes" : "no"}). ` +
        "Two-port passivity and a destabilizing pair of terminations: <code>seapass twoport check</code>.";
    },
  };

  function render(kind, r, st) {
    panelError(kind, r);
    if (!r.ok) {
      if (kind === "sampled") setVerdict($("#verdict-sampled"), "off", "not analysed", r.error);
      if (kind === "robust") setVerdict($("#verdict-robust"), "off", "not analysed", r.error);
      if (kind === "verdict") setVerdict($("#verdict-continuous"), "off", "no verdict", r.error);
      if (kind === "delay") setVerdict($("#verdict-delay"), "off", "undecided", r.error);
      return;
    }
    RENDER[kind](r.data, st);
  }

  function drawMarkers() {
    if (data.interval && S.values[data.interval.param] !== undefined && data.interval.param === S.gain) RENDER.interval(data.interval);
    if (data.region && S.region[0] === data.region.x && S.region[1] === data.region.y) Plots.region($("#plot-region"), data.region, [S.values[data.region.x], S.values[data.region.y]]);
  }

  /* ------------------------------------------------------------------ exports */
  async function exportDesign() {
    const r = await post("/api/export/design", S);
    if (!r.ok) { showErrors(r.errors || {}); setStatus(r.error, "error"); return; }
    const url = URL.createObjectURL(new Blob([r.text], { type: "application/toml" }));
    const a = document.createElement("a"); a.href = url; a.download = r.filename; document.body.appendChild(a); a.click(); a.remove();
    setTimeout(() => URL.revokeObjectURL(url), 1000);
  }

  async function exportReport() {
    const box = $("#report-status"), btn = $("#export-report");
    const r = await post("/api/export/report", { state: S, quick: $("#report-quick").checked });
    box.hidden = false;
    if (!r.ok) { box.className = "report-status failed"; box.textContent = r.error; return; }
    btn.disabled = true;
    const id = r.report.id;
    box.className = "report-status"; box.textContent = `running seapass analyze on ${r.report.design} …`;
    for (;;) {
      await new Promise((ok) => setTimeout(ok, 700));
      const s = await (await fetch(`/api/report/${id}`)).json();
      const rep = s.report;
      if (rep.status === "running") { box.textContent = `running seapass analyze on ${rep.design} … ${rep.log.trim().split("\n").pop() || ""}`; continue; }
      btn.disabled = false;
      box.className = "report-status " + rep.status; box.dataset.status = rep.status;
      box.innerHTML = rep.status === "done"
        ? `Report written to <code>${esc(rep.directory)}/report</code> in ${fmt(rep.seconds, 3)} s: <a id="report-link" href="${esc(rep.url)}" target="_blank" rel="noopener">open report.html</a>`
        : `seapass analyze failed (exit ${rep.returncode}):\n${esc(rep.log)}`;
      return;
    }
  }

  /* ------------------------------------------------------------------ start */
  async function start() {
    const init = await (await fetch("/api/initial")).json();
    KINDS = init.kinds; RESOLUTIONS = init.resolutions; CHUNK = init.chunk; PRESETS = init.presets;
    const sel = $("#preset");
    let group = null, html = sel.innerHTML;
    for (const p of PRESETS) {
      if (p.group !== group) { if (group) html += "</optgroup>"; html += `<optgroup label="${esc(p.group)}">`; group = p.group; }
      html += `<option value="${esc(p.id)}">${esc(p.label)}</option>`;
    }
    sel.innerHTML = html + "</optgroup>";
    sel.addEventListener("change", (e) => { const p = PRESETS.find((x) => x.id === sel.value); if (p) validate(clone(p.state), e.timeStamp); });
    buildConditions();
    for (const k of ["D1", "D2", "CA", "CL"]) {
      const el = $("#model-" + k);
      el.addEventListener("change", (e) => { const raw = clone(S || {}); raw.model = Object.assign({}, raw.model, { [k]: el.value }); validate(raw, e.timeStamp); });
      el.addEventListener("keydown", (e) => { if (e.key === "Enter") el.dispatchEvent(new Event("change")); });
    }
    for (const id of ["region-x", "region-y"]) $("#" + id).addEventListener("change", (e) => {
      const raw = clone(S); raw.region = [$("#region-x").value, $("#region-y").value]; validate(raw, e.timeStamp);
    });
    $("#export-design").addEventListener("click", exportDesign);
    $("#export-report").addEventListener("click", exportReport);
    $("#copy-link").addEventListener("click", (e) => { e.preventDefault(); navigator.clipboard && navigator.clipboard.writeText(location.href).then(() => setStatus("link copied", "idle"), () => {}); });
    const same = PRESETS.find((p) => p.state.name === init.state.name);
    if (same) sel.value = same.id;
    const fromUrl = decode(location.hash);
    S = init.state;
    validate(fromUrl || init.state);
  }

  window.seapass = { timings, releases, state: () => S, version: () => version, encode, decode };
  document.addEventListener("DOMContentLoaded", start);
})();
