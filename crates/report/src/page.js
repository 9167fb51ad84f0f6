// squeal's report page: reads the data block, draws the file with plotly.js, and fills the
// panel from what the pointer is over. Everything it shows comes from the file; it loads
// nothing from the network.
"use strict";
(async function () {
  const D = JSON.parse(document.getElementById("squeal-data").textContent);
  const A = D.attrs;
  const V = {};
  const PLOT_CONFIG = { displaylogo: false, responsive: true, showLink: false, showSendToCloud: false, showEditInChartStudio: false };
  const COLORS = { undecided: "#9e9e9e", steady_slip: "#1f77b4", stick_slip: "#ff7f0e", slip_oscillation: "#9467bd", not_computed: "#ffffff" };
  const REGIME_COLORS = ["#9e9e9e", "#1f77b4", "#7fb3d5", "#ff7f0e", "#c0392b", "#ffffff"];

  // ---- data ---------------------------------------------------------------------------
  async function inflate(b64) {
    const bin = atob(b64);
    const bytes = new Uint8Array(bin.length);
    for (let i = 0; i < bin.length; i++) bytes[i] = bin.charCodeAt(i);
    const stream = new Blob([bytes]).stream().pipeThrough(new DecompressionStream("deflate"));
    return new Response(stream).arrayBuffer();
  }
  async function decode(v) {
    const d = v.data;
    if (d.type === "text") return d.values;
    const buf = await inflate(d.b64);
    if (d.type === "u8") return new Uint8Array(buf);
    if (d.type === "f32") return new Float32Array(buf);
    return new Float64Array(buf);
  }
  await Promise.all(Object.entries(D.vars).map(async ([name, v]) => {
    V[name] = { shape: v.shape, dims: v.dims, attrs: v.attrs, data: await decode(v) };
  }));

  // ---- words and numbers --------------------------------------------------------------
  const num = (x) => (typeof x === "string" ? Number(x) : x);
  function fmt(x, digits = 6) {
    x = num(x);
    if (x === undefined || x === null || Number.isNaN(x)) return "n/a";
    if (!Number.isFinite(x)) return x > 0 ? "for good (inf)" : "-inf";
    if (x === 0) return "0";
    const a = Math.abs(x);
    if (a >= 1e-3 && a < 1e6) return String(Number(x.toPrecision(digits)));
    return x.toExponential(digits - 1).replace(/\.?0+e/, "e");
  }
  function flagName(v, code) {
    if (!v || !v.attrs.flag_meanings) return String(code);
    const names = v.attrs.flag_meanings.split(" ");
    const values = [].concat(v.attrs.flag_values).map(num);
    const i = values.indexOf(code);
    return i < 0 ? String(code) : names[i];
  }
  const words = (s) => String(s).replace(/_/g, " ");
  function esc(s) {
    return String(s).replace(/[&<>"]/g, (c) => ({ "&": "&amp;", "<": "&lt;", ">": "&gt;", '"': "&quot;" })[c]);
  }
  function table(rows) {
    return "<table>" + rows.filter((r) => r).map(([k, v]) => `<tr><th>${esc(k)}</th><td>${v}</td></tr>`).join("") + "</table>";
  }
  const unitsOf = (name) => (V[name] && V[name].attrs.units && V[name].attrs.units !== "1" ? " " + V[name].attrs.units : "");
  const physical = () => A.units === "physical" || Object.keys(A).some((k) => k.startsWith("physical_"));
  const isMcMillan = () => ["mcmillan", "mcmillan-nonhysteretic", "coulomb"].includes(A.law);
  function setPanel(title, html) {
    document.getElementById("panel-title").textContent = title;
    document.getElementById("panel").innerHTML = html;
  }

  // ---- parameters, provenance ---------------------------------------------------------
  const MODEL_KEYS = ["law", "nu", "lambda", "tau", "phi", "xi", "v_d", "mu_d", "mu_sd", "v_0", "mu_v", "mu_0", "a1", "a3", "dt", "solver", "scheme"];
  function subtitle(extra) {
    const parts = MODEL_KEYS.filter((k) => A[k] !== undefined).map((k) => `${k} = ${typeof A[k] === "number" ? fmt(A[k]) : A[k]}`);
    const phys = Object.keys(A).filter((k) => k.startsWith("physical_") && !/_(units|long_name)$/.test(k))
      .map((k) => `${k.slice(9)} = ${fmt(A[k])} ${A[k + "_units"] && A[k + "_units"] !== "1" ? A[k + "_units"] : ""}`.trim());
    document.getElementById("subtitle").textContent = [D.kind + ": " + (A.name || D.file), ...parts, ...phys, ...(extra || [])].join(", ");
  }
  function flagsOf(values) {
    // The command line's flags for a set of parameters (spec keys), physical or not.
    const out = [];
    if (A.law) out.push(`--law ${A.law}`);
    for (const [k, v] of Object.entries(values)) {
      if (v === undefined || typeof v !== "number" || Number.isNaN(v)) continue;
      const flag = k === "tau" && physical() ? "tau-s" : k.replace(/_/g, "-");
      out.push(`--${flag} ${Number(v.toPrecision(10))}`);
    }
    return out.join(" ");
  }
  function provenance(command) {
    const rows = [
      ["file", esc(D.file)],
      ["written by", `squeal ${esc(A.squeal_version || "?")} (git ${esc(A.git_revision || "?")})`],
      ["this page", `squeal ${esc(D.report_version)} report`],
      ["to remake it", command],
    ];
    const params = Object.entries(A).filter(([k, v]) => k !== "spec" && !/_(units|long_name)$/.test(k))
      .map(([k, v]) => [k, esc(Array.isArray(v) ? v.map((x) => fmt(x)).join(", ") : typeof v === "number" ? fmt(v, 10) : v) + esc(A[k + "_units"] && A[k + "_units"] !== "1" ? " " + A[k + "_units"] : "")]);
    document.getElementById("provenance").innerHTML = "<h2>Provenance</h2>" + table(rows) +
      (A.spec ? `<h2>Spec</h2><pre id="spec">${esc(A.spec)}</pre>` : "") +
      "<h2>Every attribute of the file</h2>" + table(params);
  }
  function thinned(what) {
    const notes = [];
    if (D.map_stride > 1) notes.push(`The maps are shown every ${D.map_stride}th row and column (${D.map_size[0]} x ${D.map_size[1]} cells in the file, at most 512 per side here).`);
    if (D.sample_stride > 1) notes.push(`Every ${D.sample_stride}th of the file's ${D.samples} samples is shown.`);
    return notes.length ? `<p class="note" id="thinned">${notes.join(" ")} ${what || ""}</p>` : "";
  }

  // ---- a basin map --------------------------------------------------------------------
  // Label codes to colour indices: undecided 0, steady slip 1, stick-slip 2, slip oscillation 3,
  // not computed 4.
  const LABEL_INDEX = { 0: 0, 1: 1, 2: 2, 3: 3, 255: 4 };
  const LABEL_SCALE = [[0, COLORS.undecided], [0.2, COLORS.undecided], [0.2, COLORS.steady_slip], [0.4, COLORS.steady_slip],
    [0.4, COLORS.stick_slip], [0.6, COLORS.stick_slip], [0.6, COLORS.slip_oscillation], [0.8, COLORS.slip_oscillation],
    [0.8, COLORS.not_computed], [1, COLORS.not_computed]];
  function mapAxes(prefix) {
    const si = V[prefix + "x0_si"] !== undefined && V[prefix + "v0_si"] !== undefined;
    const xs = si ? V[prefix + "x0_si"] : V[prefix + "x0"];
    const vs = si ? V[prefix + "v0_si"] : V[prefix + "v0"];
    return { si, x: Array.from(xs.data), v: Array.from(vs.data),
      xTitle: si ? "initial displacement x0 (m)" : "initial displacement x0 (model units: mu_k g / k)",
      vTitle: si ? "initial velocity x'0 (m/s)" : "initial velocity x'0 (model units)",
      // Equal aspect in the model's units: one unit of x as long as one unit of x'.
      ratio: si ? A.length_unit / A.velocity_unit : 1 };
  }
  function mapTrace(labels, m, ax) {
    const nv = ax.v.length, nx = ax.x.length, off = m * nv * nx, z = [];
    for (let j = 0; j < nv; j++) {
      const row = new Array(nx);
      for (let i = 0; i < nx; i++) row[i] = LABEL_INDEX[labels.data[off + j * nx + i]] ?? 0;
      z.push(row);
    }
    return { type: "heatmap", x: ax.x, y: ax.v, z, zmin: -0.5, zmax: 4.5, colorscale: LABEL_SCALE, showscale: false,
      hovertemplate: "x0 %{x}<br>x'0 %{y}<extra></extra>", name: "labels" };
  }
  function cycleTrace(xs, vs, ax) {
    const sx = ax.si ? A.length_unit : 1, sv = ax.si ? A.velocity_unit : 1;
    const x = [], v = [];
    for (let i = 0; i < xs.length; i++) if (!Number.isNaN(xs[i])) { x.push(xs[i] * sx); v.push(vs[i] * sv); }
    return { type: "scatter", mode: "lines", x, y: v, line: { color: "black", width: 2 }, name: "unstable limit cycle", hoverinfo: "skip" };
  }
  function markers(ax) {
    const t = [{ type: "scatter", mode: "markers", x: [0], y: [0], marker: { symbol: "circle-open", size: 12, color: "red", line: { width: 2 } }, name: "state at rest (0, 0)", hoverinfo: "skip" }];
    if (isMcMillan()) {
      t.push({ type: "scatter", mode: "markers", x: [ax.si ? A.length_unit : 1], y: [0], marker: { symbol: "circle-x-open", size: 12, color: "black", line: { width: 2 } }, name: "fixed point (steady slip)", hoverinfo: "skip" });
    }
    return t;
  }
  function mapLayout(ax, title) {
    return { title: { text: title }, margin: { l: 70, r: 20, t: 60, b: 60 }, hovermode: "closest",
      xaxis: { title: { text: ax.xTitle }, range: [ax.x[0], ax.x[ax.x.length - 1]], constrain: "domain" },
      yaxis: { title: { text: ax.vTitle }, scaleanchor: "x", scaleratio: ax.ratio, range: [ax.v[0], ax.v[ax.v.length - 1]], constrain: "domain" },
      legend: { orientation: "h", y: -0.15 } };
  }
  // The panel's words for one cell of map m (prefix "" for a scan, "map_" for an atlas).
  function cellRows(prefix, m, j, i) {
    const lab = V[prefix + "labels"], nv = lab.shape[lab.shape.length - 2], nx = lab.shape[lab.shape.length - 1];
    const k = m * nv * nx + j * nx + i;
    const get = (name) => (V[prefix + name] ? V[prefix + name].data[k] : undefined);
    const si = (name) => (V[prefix + name + "_si"] ? ` (${fmt(V[prefix + name + "_si"].data[k])}${unitsOf(prefix + name + "_si")})` : "");
    // The grid's coordinates have no prefix (an atlas's maps share one grid).
    const x0 = V.x0.data[i], v0 = V.v0.data[j];
    const x0si = V.x0_si ? V.x0_si.data[i] : undefined;
    const v0si = V.v0_si ? V.v0_si.data[j] : undefined;
    const label = flagName(lab, lab.data[k]);
    const rows = [
      ["start", x0si !== undefined ? `<span id="cell-start-si">x0 = ${fmt(x0si, 8)} m, x'0 = ${fmt(v0si, 8)} m/s</span> (model units: ${fmt(x0)}, ${fmt(v0)})`
        : `<span id="cell-start">x0 = ${fmt(x0, 8)}, x'0 = ${fmt(v0, 8)}</span> (model units)`],
      ["label", `<b id="cell-label">${esc(label)}</b>`],
      ["reason", esc(words(flagName(V[prefix + "reason"], get("reason"))))],
      ["decided at t", fmt(get("t_decision")) + si("t_decision")],
    ];
    if (get("t_squeal") !== undefined) rows.push(["time on stick-slip", fmt(get("t_squeal")) + si("t_squeal")]);
    const omega = get("omega");
    if (omega !== undefined && !Number.isNaN(omega)) {
      rows.push(["attractor reached", label === "stick_slip" ? "the stick-slip oscillation (squeal)" : label === "steady_slip" ? "the fixed point (steady slip)" : label === "slip_oscillation" ? "the small slip oscillation about an unstable steady slip" : "none identified"]);
      rows.push(["angular frequency of the last turn", fmt(omega) + (V[prefix + "omega_si"] ? ` (${fmt(V[prefix + "omega_si"].data[k])} Hz)` : "")]);
    }
    if (get("x_amplitude") !== undefined && !Number.isNaN(get("x_amplitude"))) {
      rows.push(["amplitude in x, x'", `${fmt(get("x_amplitude"))}, ${fmt(get("v_amplitude"))}` + (V[prefix + "x_amplitude_si"] ? ` (${fmt(V[prefix + "x_amplitude_si"].data[k])} m, ${fmt(V[prefix + "v_amplitude_si"].data[k])} m/s)` : "")]);
    }
    if (get("sticks") !== undefined) rows.push(["sticks / overtakes the belt", `${flagName(V[prefix + "sticks"], get("sticks"))} / ${flagName(V[prefix + "reverses"], get("reverses"))}`]);
    if (get("audit") !== undefined && get("audit") !== 0) rows.push(["audit (run to settlement)", esc(flagName(V[prefix + "audit"], get("audit")))]);
    return rows;
  }
  function pointNumber(ev) {
    const p = ev.points && ev.points.find((q) => q.data.name === "labels");
    if (!p) return null;
    const n = p.pointNumber;
    return Array.isArray(n) ? { j: n[0], i: n[1] } : null;
  }

  // ---- a scan -------------------------------------------------------------------------
  async function drawScan() {
    const lab = V.labels;
    if (lab.dims[0] === "sample") return drawSample();
    const nm = lab.shape.length === 3 ? lab.shape[0] : 1;
    const sweepDim = lab.shape.length === 3 ? lab.dims[0] : null;
    const swept = (m) => {
      if (!sweepDim) return [];
      const keys = sweepDim === "map" && A.swept ? A.swept.split(" ") : [sweepDim];
      return keys.filter((k) => V[k]).map((k) => {
        const siKey = ["c", "v_belt", "mu_s", "tau_si"].find((s) => V[s] && V[s].shape[0] === nm && V[s].dims[0] === sweepDim);
        return `${k} = ${fmt(V[k].data[m])}` + (siKey && siKey !== k ? ` (${siKey} = ${fmt(V[siKey].data[m])}${unitsOf(siKey)})` : "");
      });
    };
    const ax = mapAxes("");
    const gd = document.getElementById("chart");
    let current = 0;
    const controls = document.getElementById("controls");
    if (nm > 1) {
      controls.innerHTML = `<label>map <input type="range" id="map-slider" min="0" max="${nm - 1}" step="1" value="0"></label>` +
        `<button id="map-prev">previous</button> <button id="map-next">next</button> <span id="map-value"></span>`;
    }
    const cycleOf = (m) => {
      const g = nm > 1 ? `cycles/map_${String(m).padStart(4, "0")}/` : "cycle/";
      return V[g + "x"] ? cycleTrace(V[g + "x"].data, V[g + "v"].data, ax) : null;
    };
    async function show(m) {
      current = m;
      const s = swept(m);
      const title = `${A.name || "scan"}: basin map${nm > 1 ? ` ${m + 1} of ${nm}, ` : ""}${s.join(", ")}`;
      const traces = [mapTrace(lab, m, ax)];
      const c = cycleOf(m);
      if (c) traces.push(c);
      traces.push(...markers(ax));
      await Plotly.react(gd, traces, mapLayout(ax, title), PLOT_CONFIG);
      if (nm > 1) {
        document.getElementById("map-slider").value = String(m);
        document.getElementById("map-value").textContent = s.join(", ");
      }
      document.getElementById("facts").innerHTML = scanFacts(m, nm);
      document.body.dataset.map = String(m);
    }
    if (nm > 1) {
      document.getElementById("map-slider").addEventListener("input", (e) => show(Number(e.target.value)));
      document.getElementById("map-prev").addEventListener("click", () => show(Math.max(0, current - 1)));
      document.getElementById("map-next").addEventListener("click", () => show(Math.min(nm - 1, current + 1)));
    }
    await show(0);
    gd.on("plotly_hover", (ev) => {
      const c = pointNumber(ev);
      if (c) setPanel("Cell under the pointer", table(cellRows("", current, c.j, c.i)));
    });
    subtitle([`${lab.shape[lab.shape.length - 1]} x ${lab.shape[lab.shape.length - 2]} cells shown`]);
    provenance(`save the spec below as <code>${esc(A.name || "scan")}.toml</code> and run <code>squeal scan ${esc(A.name || "scan")}.toml</code>`);
  }
  function scanFacts(m, nm) {
    const at = (name) => (V[name] ? V[name].data[nm > 1 || V[name].shape[0] > m ? m : 0] : undefined);
    const rows = [];
    for (const r of ["steady_slip", "stick_slip", "slip_oscillation", "undecided"]) {
      const p = at(`basin_stability_${r}`);
      if (p === undefined) continue;
      rows.push([`basin stability: ${words(r)}`, `<span id="bs-${r}">${fmt(p, 4)} &plusmn; ${fmt(at(`basin_stability_${r}_se`), 2)}</span> (standard error; on every second cell ${fmt(at(`basin_stability_${r}_2h`), 4)})`]);
    }
    for (const f of ["cycle_r_section", "cycle_distance_plus_x", "cycle_area", "cycle_period", "cycle_multiplier"]) {
      if (at(f) !== undefined) rows.push([words(f.replace("cycle_", "unstable cycle: ")), fmt(at(f)) + (at(f + "_si") !== undefined ? ` (${fmt(at(f + "_si"))}${unitsOf(f + "_si")})` : "")]);
    }
    for (const f of ["wrong_side_cells", "audit_cells", "audit_agrees", "audit_disagrees", "audit_undecided"]) {
      if (at(f) !== undefined) rows.push([words(f), fmt(at(f))]);
    }
    if (A.rules_withdrawn) rows.push(["rules withdrawn", esc(A.rules_withdrawn)]);
    return "<h2>This map</h2>" + thinned() + table(rows);
  }
  async function drawSample() {
    const lab = V.labels, gd = document.getElementById("chart");
    const si = V.x0_si !== undefined;
    const xs = si ? V.x0_si.data : V.x0.data, vs = si ? V.v0_si.data : V.v0.data;
    const traces = [0, 1, 2, 3].map((code) => {
      const x = [], y = [], idx = [];
      for (let k = 0; k < lab.data.length && k < xs.length; k++) if (lab.data[k] === code) { x.push(xs[k]); y.push(vs[k]); idx.push(k); }
      return { type: "scattergl", mode: "markers", x, y, customdata: idx, marker: { size: 4, color: [COLORS.undecided, COLORS.steady_slip, COLORS.stick_slip, COLORS.slip_oscillation][code] }, name: ["undecided", "steady slip", "stick-slip", "slip oscillation"][code] };
    });
    await Plotly.newPlot(gd, traces, { title: { text: `${A.name || "sample"}: random starts` }, xaxis: { title: { text: si ? "x0 (m)" : "x0" } }, yaxis: { title: { text: si ? "x'0 (m/s)" : "x'0" } } }, PLOT_CONFIG);
    gd.on("plotly_hover", (ev) => {
      const k = ev.points[0].customdata;
      setPanel("Start under the pointer", table([["start", `${fmt(xs[k], 8)}, ${fmt(vs[k], 8)}`], ["label", `<b id="cell-label">${flagName(lab, lab.data[k])}</b>`]]));
    });
    document.getElementById("facts").innerHTML = scanFacts(0, 1);
    subtitle();
    provenance(`save the spec below as <code>${esc(A.name || "scan")}.toml</code> and run <code>squeal scan ${esc(A.name || "scan")}.toml</code>`);
  }

  // ---- an atlas -----------------------------------------------------------------------
  const REGIME_WORDS = { undecided: "undecided", steady_slip_only: "steady slip only (no start squeals)", bistable_quiet: "bistable, quiet from rest", bistable_squeals: "bistable, squeals from rest", fixed_point_unstable: "steady slip unstable (every start squeals)", not_computed: "not computed" };
  function boundaryParam() {
    const n = Object.keys(V).find((k) => /^critical_[a-z0-9_]+$/.test(k) && !/_(lo|hi|status|half_dt|si|err)$/.test(k));
    return n ? n.slice("critical_".length) : null;
  }
  async function drawAtlas() {
    const reg = V.regime, dims = reg.dims, gd = document.getElementById("chart");
    const p = boundaryParam();
    const coords = dims.map((d) => (V[d] ? Array.from(V[d].data) : []));
    const codes = [].concat(reg.attrs.flag_values).map(num);
    const idxOf = (c) => Math.max(0, codes.indexOf(c));
    const n = reg.data.length;
    const pointAt = (flat) => {
      const ix = [];
      let r = flat;
      for (let d = dims.length - 1; d >= 0; d--) { ix[d] = r % reg.shape[d]; r = Math.floor(r / reg.shape[d]); }
      return ix;
    };
    const scale = REGIME_COLORS.map((c, i) => [[i / 6, c], [(i + 1) / 6, c]]).flat();
    const logAxis = (vals) => vals.length > 2 && vals.every((v) => v > 0) && vals[vals.length - 1] / vals[0] > 30;
    let traces, layout;
    const pName = (d) => `${d}${unitsOf(d)}`;
    if (dims.length === 2) {
      const z = [];
      for (let j = 0; j < reg.shape[0]; j++) {
        const row = [];
        for (let i = 0; i < reg.shape[1]; i++) row.push(idxOf(reg.data[j * reg.shape[1] + i]));
        z.push(row);
      }
      traces = [{ type: "heatmap", name: "points", x: coords[1], y: coords[0], z, zmin: 0, zmax: 6, colorscale: scale, showscale: false, hovertemplate: `${dims[1]} %{x}<br>${dims[0]} %{y}<extra></extra>` }];
      layout = { xaxis: { title: { text: pName(dims[1]) }, type: logAxis(coords[1]) ? "log" : "linear" }, yaxis: { title: { text: pName(dims[0]) }, type: logAxis(coords[0]) ? "log" : "linear" } };
      // The boundaries over the other parameter, on whichever axis the damping is.
      const along = p === dims[1] ? 0 : p === dims[0] ? 1 : -1;
      for (const [name, color, dash] of [["critical", "black", "solid"], ["fold", "#c0392b", "dash"]]) {
        const b = V[`${name}_${p}`];
        if (!b || along < 0) continue;
        const values = Array.from(b.data), other = coords[along];
        traces.push({ type: "scatter", mode: "lines", name: `${name} ${p}`, line: { color, dash, width: 2 }, hoverinfo: "skip",
          x: along === 0 ? values : other, y: along === 0 ? other : values });
      }
    } else {
      const x = coords[0] || Array.from({ length: n }, (_, i) => i);
      const y = V.basin_fraction ? Array.from(V.basin_fraction.data) : x.map(() => 0);
      traces = [{ type: "scatter", mode: "markers", name: "points", x, y, marker: { size: 12, color: Array.from(reg.data).map((c) => REGIME_COLORS[idxOf(c)]), line: { color: "#333", width: 1 } }, hovertemplate: `${dims[0]} %{x}<extra></extra>` }];
      layout = { xaxis: { title: { text: pName(dims[0]) }, type: logAxis(x) ? "log" : "linear" }, yaxis: { title: { text: V.basin_fraction ? "steady-slip basin fraction" : "" } } };
      for (const [name, color, dash] of [["critical", "black", "solid"], ["fold", "#c0392b", "dash"]]) {
        const b = V[`${name}_${p}`];
        if (p === dims[0] && b && !Number.isNaN(b.data[0])) traces.push({ type: "scatter", mode: "lines", x: [b.data[0], b.data[0]], y: [0, 1], name: `${name} ${p}`, line: { color, dash, width: 2 }, hoverinfo: "skip" });
      }
    }
    Object.assign(layout, { title: { text: `${A.name || "atlas"}: regimes${p ? `, critical and fold ${p}` : ""}` }, margin: { l: 70, r: 20, t: 60, b: 60 }, hovermode: "closest", legend: { orientation: "h", y: -0.15 } });
    await Plotly.newPlot(gd, traces, layout, PLOT_CONFIG);
    const flatOf = (ev) => {
      const pt = ev.points && ev.points.find((q) => q.data.name === "points");
      if (!pt) return null;
      const pn = pt.pointNumber;
      return Array.isArray(pn) ? pn[0] * reg.shape[1] + pn[1] : pn;
    };
    gd.on("plotly_hover", (ev) => {
      const k = flatOf(ev);
      if (k !== null) setPanel("Design point under the pointer", table(pointRows(k, pointAt(k), dims, coords, p)));
    });
    gd.on("plotly_click", (ev) => {
      const k = flatOf(ev);
      if (k !== null) showPoint(k, pointAt(k), dims, coords, p);
    });
    const legend = Object.entries(REGIME_WORDS).map(([k, w], i) => `<span style="display:inline-block;width:12px;height:12px;background:${REGIME_COLORS[i]};border:1px solid #999"></span> ${w}`).join(" &nbsp; ");
    document.getElementById("facts").innerHTML = `<h2>Regimes</h2><p>${legend}</p><p class="hint">Click a point for its map, cycle, oscillation and the commands that reproduce it.</p>` + thinned();
    subtitle();
    provenance(`save the spec below as <code>${esc(A.name || "atlas")}.toml</code> and run <code>squeal atlas ${esc(A.name || "atlas")}.toml</code>`);
  }
  // The index of a point's boundary search: the point's coordinates without the damping's.
  function boundaryIndex(ix, dims, p) {
    const b = V[`critical_${p}`] || V[`fold_${p}`];
    if (!b) return null;
    if (b.dims[0] === "boundary") return 0;
    let k = 0;
    for (const d of b.dims) k = k * V[d].shape[0] + ix[dims.indexOf(d)];
    return k;
  }
  function pointRows(k, ix, dims, coords, p) {
    const reg = V.regime;
    const rows = dims.map((d, i) => [d, `${fmt(coords[i][ix[i]], 8)}${unitsOf(d)}`]);
    const rname = flagName(reg, reg.data[k]);
    rows.push(["regime", `<b id="point-regime">${esc(REGIME_WORDS[rname] || rname)}</b>`]);
    const b = p ? boundaryIndex(ix, dims, p) : null;
    if (b !== null) {
      const get = (n) => (V[n] ? V[n].data[b] : undefined);
      const st = (n) => (V[n] ? flagName(V[n], V[n].data[b]) : "");
      const si = (n) => (V[n + "_si"] ? ` = ${fmt(V[n + "_si"].data[b])}${unitsOf(n + "_si")}` : "");
      rows.push([`critical ${p} (from the operating point)`, `<span id="point-critical">${fmt(get(`critical_${p}`))}</span>${si(`critical_${p}`)} [${fmt(get(`critical_${p}_lo`))}, ${fmt(get(`critical_${p}_hi`))}] (${esc(words(st(`critical_status`)))})`]);
      const err = get(`fold_${p}_err`);
      rows.push([`fold ${p} (no start squeals above)`, `<span id="point-fold">${fmt(get(`fold_${p}`))}</span>${err !== undefined && !Number.isNaN(err) ? ` &plusmn; ${fmt(err, 2)}` : ""}${si(`fold_${p}`)} [${fmt(get(`fold_${p}_lo`))}, ${fmt(get(`fold_${p}_hi`))}] (${esc(words(st(`fold_status`)))})`]);
      if (V.boundary_note && V.boundary_note.data[b]) rows.push(["boundary note", esc(V.boundary_note.data[b])]);
    }
    if (V.basin_fraction && !Number.isNaN(V.basin_fraction.data[k])) rows.push(["steady-slip basin fraction", `${fmt(V.basin_fraction.data[k], 4)} &plusmn; ${fmt(V.basin_fraction_err ? V.basin_fraction_err.data[k] : NaN, 2)}`]);
    if (V.note && V.note.data[k]) rows.push(["note", `<span class="note">${esc(V.note.data[k])}</span>`]);
    return rows;
  }
  async function showPoint(k, ix, dims, coords, p) {
    const values = {};
    for (const key of ["nu", "lambda", "tau", "phi", "xi", "v_d", "mu_d", "mu_sd", "v_0", "mu_v", "mu_0", "a1", "a3", "m", "k", "c", "v_belt", "mu_k", "mu_s", "g", "normal_force"]) {
      if (typeof A[key] === "number") values[key] = A[key];
    }
    dims.forEach((d, i) => { values[d] = coords[i][ix[i]]; });
    if (physical()) for (const key of ["nu", "lambda", "phi"]) if (!dims.includes(key)) delete values[key];
    const flags = flagsOf(values);
    const table_ = A.law === "table" ? " --friction-csv CURVE.csv (the curve is in the file: friction_table_*)" : "";
    const stick = ["stick_omega_mean", "stick_r_mean", "stick_x_min", "stick_x_max", "stick_v_min", "stick_v_max", "stick_overshoot"]
      .filter((f) => V[f]).map((f) => [words(f.replace("stick_", "")), fmt(V[f].data[k]) + (V[f + "_si"] ? ` (${fmt(V[f + "_si"].data[k])}${unitsOf(f + "_si")})` : "")]);
    const cyc = ["cycle_r_section", "cycle_period", "cycle_multiplier", "cycle_area", "cycle_min_kick"]
      .filter((f) => V[f]).map((f) => [words(f.replace("cycle_", "")), fmt(V[f].data[k]) + (V[f + "_si"] ? ` (${fmt(V[f + "_si"].data[k])}${unitsOf(f + "_si")})` : "")]);
    const el = document.getElementById("point");
    el.innerHTML = `<h2>Selected point</h2>` + table(pointRows(k, ix, dims, coords, p)) +
      (cyc.length ? "<h2>Its unstable cycle</h2>" + table(cyc) : "") +
      (stick.length ? "<h2>Its stick-slip oscillation</h2>" + table(stick) : "") +
      `<h2>This point alone</h2><pre id="point-command">squeal ulc ${esc(flags)}${esc(table_)}\nsqueal critical ${esc(flags)}${esc(table_)}\nsqueal critical --fold ${esc(flags)}${esc(table_)}</pre>`;
    document.body.dataset.point = String(k);
    if (V.map_labels) {
      const ax = mapAxes("");
      const traces = [mapTrace(V.map_labels, k, ax)];
      if (V.map_cycle_x) {
        const np = V.map_cycle_x.shape[V.map_cycle_x.shape.length - 1];
        traces.push(cycleTrace(V.map_cycle_x.data.subarray(k * np, (k + 1) * np), V.map_cycle_v.data.subarray(k * np, (k + 1) * np), ax));
      }
      traces.push(...markers(ax));
      const gd2 = document.getElementById("second");
      gd2.style.height = "600px";
      await Plotly.newPlot(gd2, traces, mapLayout(ax, `basin map at ${dims.map((d, i) => `${d} = ${fmt(coords[i][ix[i]])}`).join(", ")}`), PLOT_CONFIG);
      gd2.on("plotly_hover", (ev) => {
        const c = pointNumber(ev);
        if (c) setPanel("Cell under the pointer", table(cellRows("map_", k, c.j, c.i)));
      });
    }
  }

  // ---- a trajectory -------------------------------------------------------------------
  async function drawTrajectory() {
    const si = V.t_si !== undefined;
    const t = V[si ? "t_si" : "t"].data, x = V[si ? "x_si" : "x"].data, v = V[si ? "v_si" : "v"].data;
    const tl = si ? "time (s)" : "time (model units, natural period 2 pi)";
    const xl = si ? "displacement x (m)" : "displacement x (model units)";
    const vl = si ? "velocity x' (m/s)" : "velocity x' (model units)";
    const gd = document.getElementById("chart");
    await Plotly.newPlot(gd, [
      { type: "scattergl", mode: "lines", x: t, y: x, name: "x", line: { color: "#1f77b4" } },
      { type: "scattergl", mode: "lines", x: t, y: v, name: "x'", yaxis: "y2", line: { color: "#ff7f0e" } },
    ], { title: { text: `${A.name || "trajectory"}: one run from x0 = ${fmt(A.x0)}, x'0 = ${fmt(A.v0)} (model units)` }, margin: { l: 70, r: 70, t: 60, b: 60 },
      xaxis: { title: { text: tl } }, yaxis: { title: { text: xl } }, yaxis2: { title: { text: vl }, overlaying: "y", side: "right" }, legend: { orientation: "h", y: -0.15 }, hovermode: "x" }, PLOT_CONFIG);
    const gd2 = document.getElementById("second");
    gd2.style.height = "520px";
    const fp = isMcMillan() ? [{ type: "scatter", mode: "markers", x: [si ? A.length_unit : 1], y: [0], name: "fixed point", marker: { symbol: "circle-x-open", size: 12, color: "black" } }] : [];
    await Plotly.newPlot(gd2, [{ type: "scattergl", mode: "lines", x, y: v, name: "phase plane", line: { color: "#444", width: 1 } }, ...fp],
      { title: { text: "phase plane" }, margin: { l: 70, r: 20, t: 50, b: 60 }, xaxis: { title: { text: xl } },
        yaxis: { title: { text: vl }, scaleanchor: "x", scaleratio: si ? A.length_unit / A.velocity_unit : 1 } }, PLOT_CONFIG);
    gd.on("plotly_hover", (ev) => {
      const k = ev.points[0].pointIndex;
      setPanel("Sample under the pointer", table([["t", fmt(t[k])], ["x", fmt(x[k])], ["x'", fmt(v[k])]]));
    });
    const rows = Object.keys(A).filter((k) => k.startsWith("lasting_") && !k.endsWith("_units")).map((k) => [words(k), fmt(A[k]) + (A[k + "_units"] ? " " + A[k + "_units"] : "")]);
    document.getElementById("facts").innerHTML = "<h2>Where it ended</h2>" + (rows.length ? table(rows) : "<p>No lasting oscillation was identified (see the file's attributes).</p>") + thinned();
    subtitle();
    const start = {};
    if (physical()) {
      for (const k of ["m", "k", "c", "v_belt", "mu_k", "mu_s", "tau", "normal_force"]) if (A["physical_" + k] !== undefined) start[k] = A["physical_" + k];
      start.x0 = A.x0 * A.length_unit; start.v0 = A.v0 * A.velocity_unit;
    } else {
      for (const k of MODEL_KEYS) if (typeof A[k] === "number" && k !== "dt") start[k] = A[k];
      start.x0 = A.x0; start.v0 = A.v0;
    }
    start.t_end = A.t_end; start.dt = A.dt;
    provenance(`<code>squeal trajectory ${esc(flagsOf(start))} --out ${esc(D.file)}</code>`);
  }

  try {
    if (D.kind === "scan") await drawScan();
    else if (D.kind === "atlas") await drawAtlas();
    else await drawTrajectory();
    document.body.dataset.ready = "1";
  } catch (e) {
    document.body.dataset.ready = "error";
    setPanel("The page could not draw this file", `<pre>${esc(e && e.stack ? e.stack : e)}</pre>`);
    throw e;
  }
})();
