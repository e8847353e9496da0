/* elastokin 3D view: moves the plotly traces of a suspension through the frames of a load
 * case (the data: the script element named by the plot's data-view attribute, written by
 * elastokin/report/view3d.py). Each part's pose per frame is a rotation vector (micro-rad) and
 * the displacement of its reference point (0.01 mm): x_now = R (x - ref) + ref + d. Config
 * frame, mm. No library but plotly.js. */
(function () {
  "use strict";
  var GAP = -2, GROUND = -1;

  function rotation(rx, ry, rz) {
    var t = Math.sqrt(rx * rx + ry * ry + rz * rz);
    if (t < 1e-12) { return [1, 0, 0, 0, 1, 0, 0, 0, 1]; }
    var x = rx / t, y = ry / t, z = rz / t, c = Math.cos(t), s = Math.sin(t), v = 1 - c;
    return [c + x * x * v, x * y * v - z * s, x * z * v + y * s,
            y * x * v + z * s, c + y * y * v, y * z * v - x * s,
            z * x * v - y * s, z * y * v + x * s, c + z * z * v];
  }

  function View(gd, figure, data, prefix) {
    this.gd = gd;
    this.figure = figure;
    this.V = data;
    this.prefix = prefix;
    this.base = figure.data.map(function (t) {
      return {x: (t.x || []).slice(), y: (t.y || []).slice(), z: (t.z || []).slice()};
    });
    this.model = data.order[0];
    this.caseName = data.models[this.model].cases[0];
    this.frame = 0;
    this.timer = null;
    this.rev = 0;
  }

  View.prototype.el = function (name) {
    return document.getElementById(this.prefix + "-" + name);
  };

  View.prototype.caseData = function (model) {
    var m = this.V.models[model];
    return m && m.data[this.caseName];
  };

  /* a beam part's data in the current case of a model, with its number of frames */
  View.prototype.beamData = function (model, part) {
    var c = this.caseData(model), b = c && c.beam && c.beam[part];
    if (!b) { return null; }
    b.count = c.steps.length;
    return b;
  };

  /* the transforms of every part of a model at the current frame: [R, ref, d] */
  View.prototype.poses = function (model) {
    var m = this.V.models[model], c = this.caseData(model), out = [];
    if (!c) { return null; }
    var n = m.parts.length, f = Math.min(this.frame, c.steps.length - 1);
    for (var p = 0; p < n; p++) {
      var o = (f * n + p) * 6, q = c.pose;
      out.push([rotation(q[o] * 1e-6, q[o + 1] * 1e-6, q[o + 2] * 1e-6), m.ref[p],
                [q[o + 3] * 0.01, q[o + 4] * 0.01, q[o + 5] * 0.01]]);
    }
    return out;
  };

  function moved(T, p, x, y, z) {
    if (p === GROUND || !T) { return [x, y, z]; }
    var R = T[p][0], r = T[p][1], d = T[p][2];
    var a = x - r[0], b = y - r[1], c = z - r[2];
    return [R[0] * a + R[1] * b + R[2] * c + r[0] + d[0],
            R[3] * a + R[4] * b + R[5] * c + r[1] + d[1],
            R[6] * a + R[7] * b + R[8] * c + r[2] + d[2]];
  }

  function rigid(base, carriers, T) {
    var xs = [], ys = [], zs = [];
    for (var i = 0; i < carriers.length; i++) {
      if (carriers[i] === GAP || base.x[i] === null) { xs.push(null); ys.push(null); zs.push(null); continue; }
      var q = moved(T, carriers[i], base.x[i], base.y[i], base.z[i]);
      xs.push(q[0]); ys.push(q[1]); zs.push(q[2]);
    }
    return [xs, ys, zs];
  }

  function helix(ends, turns, T) {
    var xs = [], ys = [], zs = [], steps = turns * 16;
    ends.forEach(function (e) {
      var a = moved(T, e[0], e[1], e[2], e[3]), b = moved(T, e[4], e[5], e[6], e[7]), r = e[8];
      var ax = [b[0] - a[0], b[1] - a[1], b[2] - a[2]];
      var L = Math.sqrt(ax[0] * ax[0] + ax[1] * ax[1] + ax[2] * ax[2]) || 1;
      var u = [ax[0] / L, ax[1] / L, ax[2] / L];
      var h = Math.abs(u[2]) < 0.9 ? [0, 0, 1] : [1, 0, 0];
      var e1 = [u[1] * h[2] - u[2] * h[1], u[2] * h[0] - u[0] * h[2], u[0] * h[1] - u[1] * h[0]];
      var n1 = Math.sqrt(e1[0] * e1[0] + e1[1] * e1[1] + e1[2] * e1[2]);
      e1 = [e1[0] / n1, e1[1] / n1, e1[2] / n1];
      var e2 = [u[1] * e1[2] - u[2] * e1[1], u[2] * e1[0] - u[0] * e1[2], u[0] * e1[1] - u[1] * e1[0]];
      for (var i = 0; i <= steps; i++) {
        var s = i / steps, th = 2 * Math.PI * turns * s, c = Math.cos(th) * r, sn = Math.sin(th) * r;
        xs.push(a[0] + ax[0] * s + c * e1[0] + sn * e2[0]);
        ys.push(a[1] + ax[1] * s + c * e1[1] + sn * e2[1]);
        zs.push(a[2] + ax[2] * s + c * e1[2] + sn * e2[2]);
      }
      xs.push(null); ys.push(null); zs.push(null);
    });
    return [xs, ys, zs];
  }

  /* per-frame points of a kinematic figure: steering axes, instant centres, roll centre */
  function figure(kind, c, f) {
    var xs = [], ys = [], zs = [];
    function put(arr, k, n) {
      for (var j = 0; j < n; j++) {
        var o = (f * n + j) * 3;
        xs.push(arr[o]); ys.push(arr[o + 1]); zs.push(arr[o + 2]);
      }
    }
    var sides = Object.keys(c.patch || {});
    if (kind === "axis") { sides.forEach(function (s) { put(c.axis[s], 0, 2); xs.push(null); ys.push(null); zs.push(null); }); }
    if (kind === "ic") { sides.forEach(function (s) { put(c.ic[s], 0, 1); }); }
    if (kind === "rc" && c.rc) { put(c.rc, 0, 1); }
    if (kind === "rcl" && c.rc) {
      sides.forEach(function (s) {
        put(c.patch[s], 0, 1); put(c.rc, 0, 1); xs.push(null); ys.push(null); zs.push(null);
      });
    }
    return [xs, ys, zs];
  }

  /* a beam part's nodes (what: "line"), its band's edge ("edge") or both (the band's mesh)
     at frame f */
  function beam(what, b, f) {
    var xs = [], ys = [], zs = [];
    if (!b) { return [xs, ys, zs]; }
    var m = b.line.length / 3 / Math.max(1, b.count);
    (what === "band" ? ["line", "edge"] : [what]).forEach(function (key) {
      var a = b[key], o = f * m * 3;
      for (var j = 0; j < m; j++) { xs.push(a[o + 3 * j]); ys.push(a[o + 3 * j + 1]); zs.push(a[o + 3 * j + 2]); }
    });
    return [xs, ys, zs];
  }

  /* arrows from points along forces at frame f (mm per N: scale), with a four-barbed head;
     and each vertex's hover text */
  function arrows(recipe, c, points, scale, f) {
    var xs = [], ys = [], zs = [], text = [], loads = c.loads || {};
    recipe.names.forEach(function (name) {
      var F, p;
      if (recipe.what === "pickup") {
        F = loads.pickup && loads.pickup[name]; p = points[name];
      } else {
        var e = loads.patch && loads.patch[name];
        F = e && e.f; p = e && e.at.slice(3 * f, 3 * f + 3);
      }
      if (!F || !p) { return; }
      var v = [F[3 * f], F[3 * f + 1], F[3 * f + 2]];
      var n = Math.sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
      var L = n * scale, tip = [p[0] + v[0] * scale, p[1] + v[1] * scale, p[2] + v[2] * scale];
      var label = name + ": " + (recipe.what === "pickup" ? "the body receives " : "the rig applies ") +
        "[" + v.map(function (x) { return x.toFixed(0); }).join(", ") + "] N, " + (n / 1000).toFixed(2) + " kN";
      function put(q) { xs.push(q[0]); ys.push(q[1]); zs.push(q[2]); text.push(label); }
      function gap() { xs.push(null); ys.push(null); zs.push(null); text.push(""); }
      put(p); put(tip); gap();
      if (L < 1e-6) { return; }
      var u = [v[0] / n, v[1] / n, v[2] / n], h = Math.min(0.25 * L, 30);
      var a = Math.abs(u[2]) < 0.9 ? [0, 0, 1] : [1, 0, 0];
      var e1 = [u[1] * a[2] - u[2] * a[1], u[2] * a[0] - u[0] * a[2], u[0] * a[1] - u[1] * a[0]];
      var k1 = Math.sqrt(e1[0] * e1[0] + e1[1] * e1[1] + e1[2] * e1[2]);
      e1 = [e1[0] / k1, e1[1] / k1, e1[2] / k1];
      var e2 = [u[1] * e1[2] - u[2] * e1[1], u[2] * e1[0] - u[0] * e1[2], u[0] * e1[1] - u[1] * e1[0]];
      [e1, e2].forEach(function (e) {
        [-1, 1].forEach(function (sg) {
          put(tip);
          put([tip[0] - h * u[0] + sg * 0.45 * h * e[0], tip[1] - h * u[1] + sg * 0.45 * h * e[1],
               tip[2] - h * u[2] + sg * 0.45 * h * e[2]]);
          gap();
        });
      });
    });
    return [xs, ys, zs, text];
  }

  /* the traces at the current frame (the figure's data, changed in place) */
  View.prototype.update = function () {
    var self = this, V = this.V, data = this.figure.data, T = {}, cmax = V.bushing_cmax;
    var c = this.caseData(this.model), f = Math.min(this.frame, c.steps.length - 1);
    V.recipes.forEach(function (recipe, k) {
      if (!recipe) { return; }
      var t = data[k];
      if (t.visible === undefined) { t.visible = true; }
      if (!recipe.ghost) {
        if (recipe.model !== self.model) { t.visible = false; return; }
        if (t.visible === false) { t.visible = true; }
      }
      if (t.visible !== true) { return; }  /* hidden from the legend: drawn when shown */
      if (!self.caseData(recipe.model)) { t.x = []; t.y = []; t.z = []; return; }
      if (!(recipe.model in T)) { T[recipe.model] = self.poses(recipe.model); }
      var P = T[recipe.model], mc = self.caseData(recipe.model), xyz = null;
      var mf = Math.min(f, mc.steps.length - 1);
      if (recipe.kind === "rigid") { xyz = rigid(self.base[k], recipe.carriers, P); }
      else if (recipe.kind === "helix") { xyz = helix(recipe.ends, recipe.turns, P); }
      else if (recipe.kind === "beam") { xyz = beam(recipe.what, self.beamData(recipe.model, recipe.part), mf); }
      else if (recipe.kind === "arrows") {
        xyz = arrows(recipe, mc, V.models[recipe.model].pickups, V.load_mm_per_N, mf);
        t.text = xyz[3];
      }
      else { xyz = figure(recipe.kind, mc, f); }
      t.x = xyz[0]; t.y = xyz[1]; t.z = xyz[2];
      if (recipe.bushings) {
        t.marker.color = recipe.bushings.map(function (b) { return mc.bushing[b] ? mc.bushing[b][f] : 0; });
        t.marker.cmax = cmax;
      }
      if (recipe.stops) {
        var col = [];
        recipe.stops.forEach(function (s) {
          var on = mc.stop[s] && mc.stop[s][f] > 0 ? 1 : 0; col.push(on, on, 0);
        });
        t.line.color = col;
      }
    });
    V.ident.forEach(function (k) {
      data[k].visible = self.caseName === "design_position" ? true : "legendonly";
    });
    this.info(c, f);
  };

  View.prototype.draw = function () {
    this.update();
    this.figure.layout.datarevision = ++this.rev;
    Plotly.react(this.gd, this.figure.data, this.figure.layout, this.figure.config);
  };

  View.prototype.info = function (c, f) {
    var parts = [this.caseName.replace(/_/g, " ")];
    if (this.caseName !== "design_position") {
      parts.push(c.branches[c.branch[f]] + ", step " + (c.steps[f] + 1) + " of " + c.n);
    } else {
      parts.push(this.V.design_note);
    }
    if (c.input && c.x) { parts.push(c.input + ": " + Number(c.x[f]).toPrecision(4)); }
    Object.keys(c.wheel || {}).forEach(function (s) {
      var w = c.wheel[s];
      parts.push((s || "wheel") + ": toe " + w[3 * f].toFixed(3) + " deg, camber " +
                 w[3 * f + 1].toFixed(3) + " deg, travel " + w[3 * f + 2].toFixed(1) + " mm");
    });
    var most = null;
    Object.keys(c.bushing || {}).forEach(function (b) {
      if (most === null || c.bushing[b][f] > c.bushing[most][f]) { most = b; }
    });
    if (most !== null) { parts.push("largest bushing deflection: " + most + " " + c.bushing[most][f].toFixed(2) + " mm"); }
    var pick = (c.loads || {}).pickup || {}, top = null, topN = -1;
    Object.keys(pick).forEach(function (p) {
      var v = pick[p], n = Math.sqrt(v[3 * f] * v[3 * f] + v[3 * f + 1] * v[3 * f + 1] + v[3 * f + 2] * v[3 * f + 2]);
      if (n > topN) { top = p; topN = n; }
    });
    if (top !== null) { parts.push("largest body pickup load: " + top + " " + (topN / 1000).toFixed(2) + " kN"); }
    this.el("info").textContent = parts.join(" \u00b7 ");
  };

  View.prototype.setCase = function (name, first) {
    this.caseName = name;
    var c = this.caseData(this.model), slider = this.el("slider");
    slider.max = String(c.steps.length - 1);
    this.frame = Math.min(this.frame, c.steps.length - 1);
    if (name === "design_position") { this.frame = 0; }
    slider.value = String(this.frame);
    slider.disabled = c.steps.length < 2;
    this.el("play").disabled = c.steps.length < 2;
    if (first) { this.update(); } else { this.draw(); }
  };

  View.prototype.fillCases = function (first) {
    var sel = this.el("case"), self = this, cases = this.V.models[this.model].cases;
    sel.innerHTML = "";
    cases.forEach(function (name) {
      var o = document.createElement("option");
      o.value = name; o.textContent = name.replace(/_/g, " ");
      sel.appendChild(o);
    });
    if (cases.indexOf(this.caseName) < 0) { this.caseName = cases[0]; }
    sel.value = this.caseName;
    self.setCase(this.caseName, first);
  };

  /* the picker of each body pickup's worst case (the model's largest force first) */
  View.prototype.fillWorst = function () {
    var sel = this.el("worst"), worst = this.V.models[this.model].worst || [];
    if (!sel) { return; }
    sel.innerHTML = "";
    var o = document.createElement("option");
    o.value = ""; o.textContent = worst.length ? "(a body pickup)" : "(no loads recorded)";
    sel.appendChild(o);
    worst.forEach(function (w, i) {
      var e = document.createElement("option");
      e.value = String(i);
      e.textContent = w.pickup + ": " + (w.force_N / 1000).toFixed(2) + " kN, " +
        w.case.replace(/_/g, " ") + " step " + w.step;
      sel.appendChild(e);
    });
    sel.disabled = !worst.length;
  };

  /* go to a pickup's worst case: its load case and frame, the pickup loads shown */
  View.prototype.showWorst = function (i) {
    var w = (this.V.models[this.model].worst || [])[i], self = this;
    if (!w) { return; }
    this.el("case").value = w.case;
    this.caseName = w.case;
    this.frame = w.frame;
    this.V.recipes.forEach(function (r, k) {
      if (r && r.kind === "arrows" && r.what === "pickup" && r.model === self.model) { self.figure.data[k].visible = true; }
    });
    this.setCase(w.case);
  };

  View.prototype.play = function () {
    var self = this, button = this.el("play");
    if (this.timer) { clearInterval(this.timer); this.timer = null; button.textContent = "\u25b6 play"; return; }
    button.textContent = "\u25a0 stop";
    this.timer = setInterval(function () {
      var n = self.caseData(self.model).steps.length;
      self.frame = (self.frame + 1) % n;
      self.el("slider").value = String(self.frame);
      self.draw();
    }, 120);
  };

  View.prototype.start = function () {
    var self = this, models = this.el("model"), gd = this.gd;
    this.V.order.forEach(function (m) {
      var o = document.createElement("option"); o.value = m; o.textContent = m; models.appendChild(o);
    });
    models.addEventListener("change", function () { self.model = models.value; self.fillWorst(); self.fillCases(); });
    if (this.el("worst")) {
      this.el("worst").addEventListener("change", function () { if (self.el("worst").value !== "") { self.showWorst(Number(self.el("worst").value)); } });
    }
    this.fillWorst();
    function picked() { if (self.el("worst")) { self.el("worst").value = ""; } }
    this.el("case").addEventListener("change", function () { picked(); self.setCase(self.el("case").value); });
    this.el("slider").addEventListener("input", function () { picked(); self.frame = Number(self.el("slider").value); self.draw(); });
    this.el("play").addEventListener("click", function () { self.play(); });
    this.fillCases(true);  /* the first frame, drawn once by newPlot */
    var fig = this.figure;
    return Plotly.newPlot(gd, fig.data, fig.layout, fig.config).then(function () {
      fig.data = gd.data;
      fig.layout = gd.layout;
      gd.on("plotly_legendclick", function () { setTimeout(function () { self.draw(); }, 0); });
      gd.setAttribute("data-ready", "1");
    });
  };

  /* the view drawn when its plot comes near the window (a long report opens at once; the
     library, kept unparsed in the script element <prefix>-plotlyjs, is run then) */
  window.elastokinLazyView = function (prefix) {
    var plot = document.getElementById(prefix + "-plot"), started = false;
    function start() {
      if (started) { return; }
      started = true;
      if (typeof Plotly === "undefined") {
        var lib = document.createElement("script");
        lib.text = document.getElementById(prefix + "-plotlyjs").textContent;
        document.head.appendChild(lib);
      }
      window.elastokinView(prefix);
    }
    if (!("IntersectionObserver" in window)) { start(); return; }
    new IntersectionObserver(function (entries, observer) {
      if (entries.some(function (e) { return e.isIntersecting; })) { observer.disconnect(); start(); }
    }, {rootMargin: "300px"}).observe(plot);
  };

  /* the view of the figure and data in the page's script elements <prefix>-figure and
     <prefix>-data, drawn into the element <prefix>-plot */
  window.elastokinView = function (prefix) {
    var gd = document.getElementById(prefix + "-plot");
    var figure = JSON.parse(document.getElementById(prefix + "-figure").textContent);
    var data = JSON.parse(document.getElementById(prefix + "-data").textContent);
    var view = new View(gd, figure, data, prefix);
    gd.elastokinView = view;
    return view.start();
  };
})();
