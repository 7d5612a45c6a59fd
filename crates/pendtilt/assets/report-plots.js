// pendtilt report: one uPlot per plot place (div.iplot, data-plot: its index), from the JSON in
// <script id="pendtilt-plots">. Drag: zoom (sideways: time; diagonal: both axes);
// Shift+wheel: zoom time about the cursor; Shift+drag: pan; double-click: back to the
// first view. The panels of one figure share their time zoom.
(function () {
  "use strict";
  var el = document.getElementById("pendtilt-plots");
  if (!el || typeof uPlot === "undefined") return;
  var D = JSON.parse(el.textContent);
  var T = D.traces;
  var plots = [];

  // Tick labels with as many decimals as the spacing needs; never "-0.0".
  function ticks(u, splits) {
    var step = splits.length > 1 ? Math.abs(splits[1] - splits[0]) : 1;
    var d = step > 0 ? Math.max(1, Math.min(6, -Math.floor(Math.log10(step) + 1e-9))) : 1;
    return splits.map(function (v) {
      var s = v.toFixed(d);
      return Number(s) === 0 ? (0).toFixed(d) : s;
    });
  }

  function value(u, v) {
    return v == null ? "-" : (Math.abs(v) < 1e-9 ? 0 : v).toFixed(4);
  }

  // Pull zoom and pan: Shift+wheel zooms time about the cursor, Shift+drag pans it.
  function zoomPan(group) {
    return {
      hooks: {
        ready: function (u) {
          var over = u.over;
          over.addEventListener("wheel", function (e) {
            if (!e.shiftKey) return;
            e.preventDefault();
            var rect = over.getBoundingClientRect();
            var at = u.posToVal(e.clientX - rect.left, "x");
            var s = u.scales.x;
            var f = (e.deltaY || e.deltaX) < 0 ? 0.75 : 1 / 0.75;
            u.setScale("x", { min: at - (at - s.min) * f, max: at + (s.max - at) * f });
          }, { passive: false });
          // capture on the root: runs before uPlot's own drag-to-zoom on the overlay
          u.root.addEventListener("mousedown", function (e) {
            if (!e.shiftKey || !over.contains(e.target)) return;
            e.stopPropagation();
            e.preventDefault();
            var x0 = e.clientX, s0 = u.scales.x.min, s1 = u.scales.x.max;
            var perPx = (s1 - s0) / over.clientWidth;
            function move(m) {
              var dx = (m.clientX - x0) * perPx;
              u.setScale("x", { min: s0 - dx, max: s1 - dx });
            }
            function up() {
              document.removeEventListener("mousemove", move);
              document.removeEventListener("mouseup", up);
            }
            document.addEventListener("mousemove", move);
            document.addEventListener("mouseup", up);
          }, true);
        },
        setScale: function (u, key) {
          if (key !== "x" || u._syncing) return;
          group.forEach(function (o) {
            if (o === u) return;
            o._syncing = true;
            o.setScale("x", { min: u.scales.x.min, max: u.scales.x.max });
            o._syncing = false;
          });
        },
        drawAxes: function (u) {
          var ctx = u.ctx, b = u.bbox;
          (u._shades || []).forEach(function (s) {
            var a = Math.max(u.valToPos(s.from_to[0], "x", true), b.left);
            var z = Math.min(u.valToPos(s.from_to[1], "x", true), b.left + b.width);
            if (z <= a) return;
            ctx.fillStyle = s.colour;
            ctx.fillRect(a, b.top, z - a, b.height);
          });
        }
      }
    };
  }

  var groups = {};
  document.querySelectorAll("div.iplot").forEach(function (div) {
    var p = D.plots[+div.getAttribute("data-plot")];
    var key = div.getAttribute("data-group") || div.getAttribute("data-plot");
    var group = groups[key] || (groups[key] = []);
    var data = [T[p.x]].concat(p.series.map(function (s) { return T[s.data]; }));
    var opts = {
      title: p.title,
      width: Math.max(300, div.clientWidth || 1000),
      height: 280,
      cursor: {
        drag: { x: true, y: true, uni: 40 },
        bind: {
          dblclick: function (u) {
            return function () {
              u.batch(function () {
                u.setScale("x", { min: p.xr[0], max: p.xr[1] });
                u.setScale("y", { min: p.yr[0], max: p.yr[1] });
              });
              return null;
            };
          }
        }
      },
      scales: {
        // first view: the figure's ranges; then whatever the zoom sets (y is ranged
        // only while never set, so a zoom in time keeps the ordinate steady)
        x: {
          time: false, auto: false,
          range: function (u, a, b) { return a == null || b == null ? [p.xr[0], p.xr[1]] : [a, b]; }
        },
        y: { auto: false, range: function () { return [p.yr[0], p.yr[1]]; } }
      },
      axes: [
        { label: p.xl, values: ticks },
        { label: p.yl, values: ticks, size: 70 }
      ],
      series: [{ label: p.xl, value: value }].concat(p.series.map(function (s) {
        return { label: s.name, stroke: s.colour, width: s.width, value: value, spanGaps: false };
      })),
      plugins: [zoomPan(group)]
    };
    var u = new uPlot(opts, data, div);
    u._shades = p.shades;
    u.redraw();
    group.push(u);
    plots.push(u);
  });

  window.addEventListener("resize", function () {
    plots.forEach(function (u) {
      var w = Math.max(300, u.root.parentNode.clientWidth || 1000);
      u.setSize({ width: w, height: 280 });
    });
  });
  // for tests and the console
  window.pendtiltPlots = plots;
  window.pendtiltTicks = ticks;
})();
