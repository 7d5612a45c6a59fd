// Opens report pages in headless Chromium (the system's, no download) and checks that the
// interactive plots work: no console error or network request, one uPlot per plot, a drag
// zooms in (the figure's other panels follow), Shift+drag pans, a double-click zooms back
// out, no tick label reads "-0.0".
// Usage: node check-report.js PAGE.html [PAGE.html ...]  (CHROMIUM=/path overrides)
"use strict";
const path = require("path");
const { chromium } = require("playwright-core");

const FLAGS = [
  "--headless", "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
  "--disable-background-networking", "--disable-component-update", "--disable-sync",
];

function fail(page, msg) {
  throw new Error(`${page}: ${msg}`);
}

async function check(browser, file) {
  const page = await browser.newPage({ viewport: { width: 1400, height: 1000 } });
  const errors = [];
  page.on("console", (m) => { if (m.type() === "error") errors.push(m.text()); });
  page.on("pageerror", (e) => errors.push(String(e)));
  // nothing may come from the network: the page is self-contained
  await page.route(/^(https?|wss?):/, (r) => { errors.push(`network: ${r.request().url()}`); r.abort(); });
  await page.goto("file://" + path.resolve(file));
  await page.waitForFunction(() => Array.isArray(window.pendtiltPlots), null, { timeout: 20000 });
  const n = await page.evaluate(() => ({
    divs: document.querySelectorAll("div.iplot").length,
    plots: window.pendtiltPlots.length,
    drawn: document.querySelectorAll("div.iplot .uplot canvas").length,
    json: document.getElementById("pendtilt-plots").textContent.length,
  }));
  if (n.divs === 0) fail(file, "no interactive plot on the page");
  if (n.plots !== n.divs || n.drawn !== n.divs) {
    fail(file, `${n.divs} plot places, ${n.plots} uPlot instances, ${n.drawn} canvases`);
  }
  const xr = () => page.evaluate(() => {
    const s = window.pendtiltPlots[0].scales.x;
    return [s.min, s.max];
  });
  const before = await xr();
  const over = page.locator("div.iplot").first().locator(".u-over");
  await over.scrollIntoViewIfNeeded();
  const box = await over.boundingBox();
  const y = box.y + box.height / 2;
  // drag sideways over the middle fifth: time zoom
  await page.mouse.move(box.x + box.width * 0.4, y);
  await page.mouse.down();
  await page.mouse.move(box.x + box.width * 0.5, y + 2, { steps: 5 });
  await page.mouse.move(box.x + box.width * 0.6, y + 2, { steps: 5 });
  await page.mouse.up();
  const zoomed = await xr();
  const span = (r) => r[1] - r[0];
  if (!(span(zoomed) < 0.5 * span(before) && zoomed[0] > before[0] && zoomed[1] < before[1])) {
    fail(file, `drag did not zoom in: x range ${before} -> ${zoomed}`);
  }
  // the other panels of the same figure follow
  const synced = await page.evaluate(() => {
    const divs = [...document.querySelectorAll("div.iplot")];
    const g = divs[0].getAttribute("data-group");
    const u0 = window.pendtiltPlots[0];
    return window.pendtiltPlots.every((u, i) =>
      divs[i].getAttribute("data-group") !== g ||
      (Math.abs(u.scales.x.min - u0.scales.x.min) < 1e-9 && Math.abs(u.scales.x.max - u0.scales.x.max) < 1e-9));
  });
  if (!synced) fail(file, "the panels of the first figure did not follow its zoom");
  // Shift+drag pans by about the dragged width
  await page.keyboard.down("Shift");
  await page.mouse.move(box.x + box.width * 0.6, y);
  await page.mouse.down();
  await page.mouse.move(box.x + box.width * 0.4, y, { steps: 5 });
  await page.mouse.up();
  await page.keyboard.up("Shift");
  const panned = await xr();
  if (!(panned[0] > zoomed[0] && Math.abs(span(panned) - span(zoomed)) < 1e-6 * span(before))) {
    fail(file, `Shift+drag did not pan: ${zoomed} -> ${panned}`);
  }
  await page.mouse.dblclick(box.x + box.width / 2, y);
  const reset = await xr();
  if (Math.abs(reset[0] - before[0]) > 1e-9 || Math.abs(reset[1] - before[1]) > 1e-9) {
    fail(file, `double-click did not restore the range: ${before} -> ${reset}`);
  }
  // tick labels: never "-0", "-0.0", ..., also on an ordinate a rounding error from zero
  const negZero = await page.evaluate(async () => {
    const u = window.pendtiltPlots[0];
    // the formatter itself, on a split a rounding error below zero (0.1 * 3 - 0.3)
    const bad = window.pendtiltTicks(u, [-0.2, 0.3 - 0.1 * 3, 0.2]).filter((v) => v !== "0.0" && Number(v) === 0);
    for (const [a, b] of [[-0.35, 0.25], [-0.7, 0.5], [-3.3, 2.1]]) {
      u.setScale("y", { min: a, max: b });
      await new Promise((r) => requestAnimationFrame(r));
      for (const ax of u.axes) {
        for (const v of ax._values || []) if (/^-0(\.0*)?$/.test(String(v))) bad.push(v);
      }
    }
    return bad;
  });
  if (negZero.length) fail(file, `tick labels reading negative zero: ${negZero}`);
  if (errors.length) fail(file, "console errors:\n  " + errors.join("\n  "));
  console.log(`${file}: ${n.plots} plots, ${(n.json / 1e6).toFixed(2)} MB of plot data; ` +
    `zoom ${before.map((v) => v.toFixed(2))} -> ${zoomed.map((v) => v.toFixed(2))}, pan, reset: ok`);
  await page.close();
}

(async () => {
  const files = process.argv.slice(2);
  if (!files.length) {
    console.error("usage: node check-report.js PAGE.html [...]");
    process.exit(2);
  }
  const browser = await chromium.launch({
    executablePath: process.env.CHROMIUM || "/usr/bin/chromium",
    args: FLAGS,
  });
  let ok = true;
  for (const f of files) {
    try {
      await check(browser, f);
    } catch (e) {
      ok = false;
      console.error(String(e.message || e));
    }
  }
  await browser.close();
  process.exit(ok ? 0 : 1);
})();
