// The history page's style, controls and script, kept apart from the C++ that fills in the data
// so that each reads as what it is. The script builds every element with textContent (never
// innerHTML): labels, host names and branches are data, not markup.
#include "harness/results/dashboard_page.hpp"

namespace suite::dashboard_detail {

const char* const page_style =
    R"css(:root { --ink: #1d2330; --muted: #5b6474; --line: #d9dee7; --median: #1f5fa8; --gate: #b35c00; --worse: #c62828; --better: #2e7d32; }
* { box-sizing: border-box; }
[hidden] { display: none !important; }
body { margin: 0; font: 14px/1.45 system-ui, "DejaVu Sans", "Liberation Sans", sans-serif; color: var(--ink); background: #f3f5f8; }
header.top { position: sticky; top: 0; z-index: 1; background: #fff; border-bottom: 1px solid var(--line); padding: 12px 24px 10px; }
h1 { font-size: 20px; margin: 0 0 2px; }
.summary { margin: 0 0 8px; color: var(--muted); }
.zero { margin: 12px 24px 0; color: var(--muted); }
.filters { display: flex; flex-wrap: wrap; gap: 8px 20px; align-items: center; }
.filters select { font: inherit; padding: 2px 4px; max-width: 30em; }
#shown { color: var(--muted); margin-left: auto; }
.legend { margin: 8px 0 0; color: var(--muted); font-size: 12px; display: flex; flex-wrap: wrap; gap: 4px 18px; align-items: center; }
.key { display: inline-block; vertical-align: middle; margin-right: 6px; }
.key.median { width: 10px; height: 10px; border-radius: 50%; background: var(--median); }
.key.unstable { width: 10px; height: 10px; border-radius: 50%; border: 2px solid var(--median); background: #fff; }
.key.band { width: 20px; height: 12px; background: linear-gradient(transparent 5px, var(--median) 5px, var(--median) 7px, transparent 7px), rgba(31, 95, 168, 0.16); }
.key.gate { width: 20px; height: 12px; background: repeating-linear-gradient(90deg, var(--gate) 0 4px, transparent 4px 7px) center / 100% 2px no-repeat, rgba(214, 123, 0, 0.18); }
.key.step { width: 0; height: 14px; border-left: 2px dashed; }
.key.worse { border-color: var(--worse); }
.key.better { border-color: var(--better); }
main { padding: 4px 24px 32px; }
section.machine h2 { font-size: 16px; margin: 18px 0 8px; }
.grid { display: grid; grid-template-columns: repeat(auto-fill, minmax(540px, 1fr)); gap: 14px; }
.card { background: #fff; border: 1px solid var(--line); border-radius: 6px; padding: 10px 12px 8px; min-width: 0; }
.card.has-worse { border-left: 4px solid var(--worse); }
.card h3 { font: 600 14px/1.3 ui-monospace, "DejaVu Sans Mono", monospace; margin: 0; overflow-wrap: anywhere; }
.meta { margin: 2px 0 0; color: var(--muted); font-size: 12px; }
.gate { margin: 2px 0 0; color: var(--gate); font-size: 12px; }
.gate.none { color: var(--muted); font-style: italic; }
.steps { list-style: none; margin: 4px 0 0; padding: 0; font-size: 12px; }
.steps .worse { color: var(--worse); }
.steps .better { color: var(--better); }
.plot { position: relative; height: 240px; margin-top: 6px; }
.empty, .failure { margin: 32px 24px; padding: 16px 20px; background: #fff; border: 1px solid var(--line); border-radius: 6px; }
.failure { color: var(--worse); border-color: var(--worse); }
)css";

const char* const page_controls = R"html(<nav class="filters">
<label>Machine <select id="machine"><option value="">all machines</option></select></label>
<label>Kernel <select id="kernel"><option value="">all kernels</option></select></label>
<label><input type="checkbox" id="steps-only"> only series with a step</label>
<span id="shown"></span>
</nav>
<p class="legend"><span><span class="key median"></span>median of a run</span><span><span class="key unstable"></span>unstable run (drawn, not used to find steps or the band)</span><span><span class="key band"></span>repetitions' spread: median &plusmn; noise, within one run</span><span><span class="key gate"></span>runs' band: the gate's band (last <span id="band-window">N</span> runs), where <code>history check</code> expects the next run</span><span><span class="key step worse"></span>step, worse</span><span><span class="key step better"></span>step, better</span></p>
)html";

const char* const page_script = R"js("use strict";
(function () {
  const MEDIAN = "#1f5fa8", BAND = "rgba(31, 95, 168, 0.16)", WORSE = "#c62828", BETTER = "#2e7d32";
  const GATE = "#b35c00", GATE_FILL = "rgba(214, 123, 0, 0.18)";
  const body = document.body;
  const failure = document.getElementById("failure");
  function fail(why) {
    failure.textContent = why;
    failure.hidden = false;
    body.dataset.failed = why;
  }
  window.addEventListener("error", (event) => fail("The page's script failed: " + event.message));

  const data = JSON.parse(document.getElementById("history-data").textContent);
  if (typeof Chart === "undefined") {
    console.error("chart.min.js did not load");
    fail("chart.min.js did not load: it belongs beside index.html (suite history html writes both).");
    return;
  }

  const short = (commit) => commit.replace(/^([0-9a-f]{7})[0-9a-f]+/, "$1");
  const number = (v) => (typeof v !== "number" || !isFinite(v) ? "n/a" : String(Number(v.toPrecision(4))));
  const percent = (r) => (r > 0 ? "+" : "") + (100 * r).toFixed(1) + " %";
  const stepText = (st) => "step at " + short(st.commit) + ": " + percent(st.change);
  // The runs' band, history check's (history_band.hpp): where it expects the next run's median
  // if nothing changed. Its spread is taken over the runs' log medians, so it is relative and
  // reads as a percentage.
  const gateLabel = (band) => "runs' band: the gate's band (last " + band.runs + " runs)";
  function bandText(series) {
    const b = series.band;
    if (!b) return "runs' band: " + (series.band_reason || "none");
    return gateLabel(b) + ": " + number(b.low) + " to " + number(b.high) + " " + series.unit + ", centre " + number(b.centre) +
           ", runs' spread " + (100 * b.spread).toFixed(1) + " %";
  }
  function element(tag, className, text) {
    const e = document.createElement(tag);
    if (className) e.className = className;
    if (text !== undefined) e.textContent = text;
    return e;
  }

  // Debian's Chart.js 3 has no annotation plugin: each step is a dashed line between the last
  // entry of the old level and the first of the new one, its text at the top of the plot.
  function stepMarkers(series) {
    return {
      id: "stepMarkers",
      afterDatasetsDraw(chart) {
        const { ctx, chartArea: area, scales: { x } } = chart;
        ctx.save();
        ctx.font = "12px system-ui, 'DejaVu Sans', sans-serif";
        ctx.textBaseline = "top";
        series.steps.forEach((st, i) => {
          const colour = st.worse ? WORSE : BETTER;
          const here = x.getPixelForValue(st.index);
          const at = st.index > 0 ? (here + x.getPixelForValue(st.index - 1)) / 2 : here;
          ctx.strokeStyle = colour;
          ctx.lineWidth = 1.5;
          ctx.setLineDash([5, 4]);
          ctx.beginPath();
          ctx.moveTo(at, area.top);
          ctx.lineTo(at, area.bottom);
          ctx.stroke();
          const text = stepText(st);
          const width = ctx.measureText(text).width;
          const left = at + 6 + width > area.right ? at - 6 - width : at + 6;
          const top = area.top + 4 + 16 * i;
          ctx.fillStyle = "rgba(255, 255, 255, 0.85)";
          ctx.fillRect(left - 2, top - 1, width + 4, 15);
          ctx.fillStyle = colour;
          ctx.fillText(text, left, top);
        });
        ctx.restore();
      },
    };
  }

  // Datasets: the repetitions' spread's lower and upper edges (filled between), the medians, the
  // steps' points; then, drawn beneath them (order 1), the runs' band over the entries of its
  // window, its edges filled between and its centre dashed.
  function draw(canvas, series) {
    const entries = series.entries, band = series.band;
    const overWindow = (v) => entries.map((e, i) => (i >= band.first ? v : null));
    const edge = { borderWidth: 0, pointRadius: 0, pointHitRadius: 0, order: 1 };
    const gate = !band ? [] : [
      { ...edge, label: gateLabel(band) + ", low", data: overWindow(band.low), fill: false },
      { ...edge, label: gateLabel(band) + ", high", data: overWindow(band.high), fill: "-1", backgroundColor: GATE_FILL },
      { ...edge, label: gateLabel(band) + ", centre", data: overWindow(band.centre), fill: false, borderWidth: 1.5, borderColor: GATE, borderDash: [6, 4] },
    ];
    const level = (e, k) => (typeof e.median === "number" ? e.median * (1 + k * e.noise) : null);
    const stepAt = new Map(series.steps.map((st) => [st.index, st]));
    const atStep = (i, yes, no) => (stepAt.has(i) ? yes(stepAt.get(i)) : no);
    // No figure here is negative (rates, times, counts): where the repetitions' spread or the
    // grace would take the axis below 0, it starts at 0.
    const shownValues = entries.flatMap((e) => [level(e, -1), level(e, 1)]).concat(band ? [band.low, band.high] : [])
      .filter((v) => typeof v === "number" && isFinite(v));
    const lowest = Math.min(...shownValues), highest = Math.max(...shownValues);
    const floor = lowest - 0.1 * (highest - lowest) < 0 || lowest < 0 ? { min: 0, beginAtZero: true } : {};
    return new Chart(canvas, {
      type: "line",
      data: {
        labels: entries.map((e) => short(e.commit)),
        datasets: [
          { label: "repetitions' spread, low", data: entries.map((e) => level(e, -1)), borderWidth: 0, pointRadius: 0, pointHitRadius: 0, fill: false },
          { label: "repetitions' spread, high", data: entries.map((e) => level(e, 1)), borderWidth: 0, pointRadius: 0, pointHitRadius: 0, fill: "-1",
            backgroundColor: BAND },
          {
            label: "median",
            data: entries.map((e) => e.median),
            borderColor: MEDIAN, borderWidth: 2, tension: 0,
            pointRadius: entries.map((e) => (e.unstable ? 4 : 3)),
            pointBorderWidth: entries.map((e) => (e.unstable ? 2 : 1)),
            pointBackgroundColor: entries.map((e) => (e.unstable ? "#ffffff" : MEDIAN)),
            pointBorderColor: MEDIAN,
          },
          {
            data: entries.map((e, i) => atStep(i, () => e.median, null)),
            showLine: false, pointStyle: "triangle", pointRadius: 7, pointBorderColor: "#ffffff",
            pointRotation: entries.map((e, i) => atStep(i, (st) => (st.change < 0 ? 180 : 0), 0)),
            pointBackgroundColor: entries.map((e, i) => atStep(i, (st) => (st.worse ? WORSE : BETTER), BETTER)),
          },
          ...gate,
        ],
      },
      options: {
        animation: false, responsive: true, maintainAspectRatio: false,
        interaction: { mode: "index", intersect: false },
        plugins: {
          legend: { display: false },
          tooltip: {
            filter: (item) => item.datasetIndex === 2,
            callbacks: {
              title: (items) => { const e = entries[items[0].dataIndex]; return e.commit + (e.branch ? " on " + e.branch : ""); },
              label: (item) => {
                const e = entries[item.dataIndex];
                return "median " + number(e.median) + " " + series.unit + (e.noise > 0 ? " ± " + (100 * e.noise).toFixed(1) + " %" : "");
              },
              afterLabel: (item) => {
                const e = entries[item.dataIndex];
                const lines = [e.date + ", run " + e.run_id + (e.samples ? ", " + e.samples + " repetitions" : "")];
                if (e.unstable) lines.push("unstable: drawn, not used to find steps or the band");
                atStep(item.dataIndex, (st) => lines.push(stepText(st)), null);
                lines.push(bandText(series));
                return lines;
              },
            },
          },
        },
        scales: {
          x: { offset: true, grid: { display: false }, ticks: { maxRotation: 0, autoSkipPadding: 10, font: { family: "monospace" } } },
          y: { grace: "10%", title: { display: true, text: series.figure + " (" + series.unit + ")" }, ...floor },
        },
      },
      plugins: [stepMarkers(series)],
    });
  }

  // One section a machine, one card a series, in the order the history gave them.
  const main = document.getElementById("charts");
  const sections = new Map(), cards = [];
  for (const series of data.series) {
    if (!sections.has(series.fingerprint)) {
      const section = element("section", "machine"), grid = element("div", "grid");
      section.append(element("h2", "", series.machine), grid);
      main.appendChild(section);
      sections.set(series.fingerprint, { section, grid, label: series.machine });
    }
    const card = element("article", "card");
    card.dataset.machine = series.fingerprint;
    card.dataset.kernel = series.kernel;
    card.dataset.steps = String(series.steps.length);
    if (series.steps.some((st) => st.worse)) card.classList.add("has-worse");
    const runs = series.entries.length;
    const meta = [series.figure + " in " + series.unit, series.direction + " is better", series.context, runs + (runs === 1 ? " run" : " runs")];
    card.append(element("h3", "", series.label), element("p", "meta", meta.filter(Boolean).join(" · ")),
                element("p", series.band ? "gate" : "gate none", bandText(series)));
    if (series.steps.length) {
      const list = element("ul", "steps");
      for (const st of series.steps)
        list.appendChild(element("li", st.worse ? "worse" : "better", stepText(st) + ", " + (st.worse ? "worse" : "better") + " (" +
          number(st.before) + " → " + number(st.after) + " " + series.unit + ", p = " + number(st.p) + ")"));
      card.appendChild(list);
    }
    const plot = element("div", "plot"), canvas = element("canvas");
    canvas.setAttribute("role", "img");
    canvas.setAttribute("aria-label", series.label + ": " + series.figure + " over " + runs + " runs");
    plot.appendChild(canvas);
    card.appendChild(plot);
    sections.get(series.fingerprint).grid.appendChild(card);
    cards.push({ card, canvas, series });
  }

  // The filters show and hide cards; a machine whose cards are all hidden hides its heading too.
  const machine = document.getElementById("machine"), kernel = document.getElementById("kernel");
  const stepsOnly = document.getElementById("steps-only"), shown = document.getElementById("shown");
  const labels = [...sections.values()].map((s) => s.label);
  for (const [fingerprint, s] of sections) {
    const twice = labels.indexOf(s.label) !== labels.lastIndexOf(s.label);
    machine.appendChild(new Option(twice ? s.label + " [" + fingerprint.slice(0, 8) + "]" : s.label, fingerprint));
  }
  for (const k of [...new Set(data.series.map((s) => s.kernel))].sort()) kernel.appendChild(new Option(k, k));
  document.getElementById("band-window").textContent = String(data.window);
  function applyFilters() {
    let visible = 0;
    for (const { card } of cards) {
      const show = (!machine.value || card.dataset.machine === machine.value) && (!kernel.value || card.dataset.kernel === kernel.value) &&
                   (!stepsOnly.checked || card.dataset.steps !== "0");
      card.hidden = !show;
      visible += show ? 1 : 0;
    }
    for (const { section, grid } of sections.values()) section.hidden = ![...grid.children].some((c) => !c.hidden);
    shown.textContent = "showing " + visible + " of " + cards.length + " charts";
    body.dataset.shown = String(visible);
  }
  for (const control of [machine, kernel, stepsOnly]) control.addEventListener("change", applyFilters);

  // Counts that were 0 in every run: one line, no chart.
  if (data.all_zero.length) {
    const names = data.all_zero.map((z) => z.label + " " + z.figure + (data.all_zero.some((y) => y.machine !== z.machine) ? " on " + z.machine : ""));
    const zero = element("p", "zero", "0 in every run, not charted (" + names.length + "): " + names.join("; "));
    zero.id = "all-zero";
    main.prepend(zero);
  }
  for (const c of cards) draw(c.canvas, c.series);
  applyFilters();

  // A drawn chart shows its medians' colour; a blank or failed one does not. data-drawn counts
  // the charts that do, for the browser test and for anyone who wonders why a card is empty.
  function inked(canvas) {
    const { width, height } = canvas;
    if (!width || !height) return false;
    const px = canvas.getContext("2d").getImageData(0, 0, width, height).data;
    for (let i = 0; i < px.length; i += 4)
      if (px[i + 3] > 200 && Math.abs(px[i] - 31) < 40 && Math.abs(px[i + 1] - 95) < 40 && Math.abs(px[i + 2] - 168) < 40) return true;
    return false;
  }
  requestAnimationFrame(() => {
    body.dataset.charts = String(cards.length);
    body.dataset.drawn = String(cards.filter((c) => inked(c.canvas)).length);
  });
})();
)js";

}  // namespace suite::dashboard_detail
