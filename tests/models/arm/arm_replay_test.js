#!/usr/bin/env node
// The picture `stsim arm SCENARIO --out DIR` writes, replay.html, in a real browser: Debian's
// chromium, headless, driven over the DevTools protocol on a pipe (as tests/models/pool's
// pool_page_test.js: JSON messages separated by NUL on fds 3 and 4, nothing from npm). For
// shipped scenarios it checks the page against the run's own files, not against itself:
//   - the file is self-contained (no URL it would fetch) and bounded (poses subsampled);
//   - both views draw one shape per arm capsule, obstacle and person part (summary.json's
//     counts, 12 parts a person);
//   - the timeline marks as many STOPs as summary.json's `stops` and warnings.csv's STOP rows;
//   - at each STOP the highlighted pair is warnings.csv's pair with the arm's smallest TTC at
//     that cycle (ties: the closer), and the frame shown is the STOP's cycle;
//   - persons are drawn when present.
// Screenshots of a STOP go to --out.
//
//   node arm_replay_test.js --stsim build/stsim --scenarios models/arm/scenarios --out DIR [--chromium PATH]
"use strict";
const {spawn, spawnSync} = require("child_process");
const fs = require("fs");
const path = require("path");

const args = {chromium: "/usr/bin/chromium"};
for (let i = 2; i < process.argv.length; i += 2) args[process.argv[i].replace(/^--/, "")] = process.argv[i + 1];
if (!args.stsim || !args.out || !args.scenarios) {
  console.error("usage: arm_replay_test.js --stsim STSIM --scenarios DIR --out DIR [--chromium PATH]");
  process.exit(2);
}
fs.rmSync(args.out, {recursive: true, force: true});
fs.mkdirSync(args.out, {recursive: true});
const children = [];
function fail(message) {
  console.error("arm_replay_test: FAIL: " + message);
  for (const c of children) c.kill("SIGKILL");
  process.exit(1);
}
const overall = setTimeout(() => fail("took more than 150 s"), 150000);
const sleep = ms => new Promise(r => setTimeout(r, ms));

// ---- the run and its own files
function runArm(scenario, tag, extra) {
  const out = path.join(args.out, tag);
  const r = spawnSync(args.stsim, ["arm", path.join(args.scenarios, scenario), "--out", out, ...extra],
                      {encoding: "utf8", timeout: 60000});
  if (r.status !== 0) fail(`stsim arm ${scenario}: exit ${r.status}: ${r.stdout}${r.stderr}`);
  const summary = JSON.parse(fs.readFileSync(path.join(out, "summary.json"), "utf8"));
  const lines = fs.readFileSync(path.join(out, "warnings.csv"), "utf8").trim().split("\n");
  const head = lines[0].split(",");
  const col = n => head.indexOf(n);
  // no field of the shipped scenarios' warnings holds a comma
  const warnings = lines.slice(1).filter(l => l).map(l => {
    const f = l.split(",");
    return {t: f[col("t_s")], arm: f[col("arm")], link: f[col("link")], other: f[col("other")],
            d: +f[col("distance_m")], ttc: f[col("ttc_s")] === "inf" ? Infinity : +f[col("ttc_s")], stop: f[col("stop")] === "STOP"};
  });
  const html = fs.readFileSync(path.join(out, "replay.html"), "utf8");
  return {out, summary, warnings, html};
}

// ---- the browser, over the DevTools protocol on a pipe
class Browser {
  constructor() {
    this.proc = spawn(args.chromium, [
      "--headless=new", "--remote-debugging-pipe", "--no-sandbox", "--disable-gpu", "--no-first-run",
      "--no-default-browser-check", "--disable-extensions", "--window-size=1400,900",
      `--user-data-dir=${path.join(args.out, "profile")}`, "about:blank"],
      {stdio: ["ignore", "ignore", "pipe", "pipe", "pipe"]});
    children.push(this.proc);
    this.proc.stderr.on("data", () => {});
    this.next = 1;
    this.waiting = new Map();
    this.exceptions = [];  // the pages' uncaught errors
    this.requests = [];    // every URL a page asked for
    let buf = Buffer.alloc(0);
    this.proc.stdio[4].on("data", d => {
      buf = Buffer.concat([buf, d]);
      for (let z; (z = buf.indexOf(0)) >= 0;) {
        const m = JSON.parse(buf.subarray(0, z).toString("utf8"));
        buf = buf.subarray(z + 1);
        if (m.id && this.waiting.has(m.id)) {
          const w = this.waiting.get(m.id);
          this.waiting.delete(m.id);
          if (m.error) w.reject(new Error(`${w.method}: ${m.error.message}`));
          else w.resolve(m.result);
        } else if (m.method === "Runtime.exceptionThrown") {
          const d = m.params.exceptionDetails;
          this.exceptions.push(d.exception ? d.exception.description : d.text);
        } else if (m.method === "Network.requestWillBeSent") {
          this.requests.push(m.params.request.url);
        }
      }
    });
  }
  send(method, params = {}, sessionId = undefined) {
    const id = this.next++;
    const msg = {id, method, params};
    if (sessionId) msg.sessionId = sessionId;
    this.proc.stdio[3].write(JSON.stringify(msg) + "\0");
    return new Promise((resolve, reject) => {
      this.waiting.set(id, {resolve, reject, method});
      setTimeout(() => reject(new Error(`${method}: no answer in 30 s`)), 30000).unref();
    });
  }
  async open(url) {
    const {targetId} = await this.send("Target.createTarget", {url: "about:blank"});
    const {sessionId} = await this.send("Target.attachToTarget", {targetId, flatten: true});
    const page = new Page(this, sessionId);
    await page.cmd("Page.enable");
    await page.cmd("Runtime.enable");
    await page.cmd("Emulation.setDeviceMetricsOverride", {width: 1400, height: 900, deviceScaleFactor: 1, mobile: false});
    // the page may fetch nothing: every request but the file itself fails the test
    await page.cmd("Network.enable");
    await page.cmd("Page.navigate", {url});
    return page;
  }
}
class Page {
  constructor(browser, sessionId) { this.browser = browser; this.sessionId = sessionId; }
  cmd(method, params) { return this.browser.send(method, params, this.sessionId); }
  async eval(expression) {
    const r = await this.cmd("Runtime.evaluate", {expression, returnByValue: true, awaitPromise: true});
    if (r.exceptionDetails) throw new Error(`${expression}: ${r.exceptionDetails.exception ? r.exceptionDetails.exception.description : r.exceptionDetails.text}`);
    return r.result.value;
  }
  async waitFor(expression, what, timeoutMs = 30000) {
    const end = Date.now() + timeoutMs;
    let last = null;
    while (Date.now() < end) {
      try { if (await this.eval(expression)) return; } catch (e) { last = e; }
      await sleep(50);
    }
    fail(`waited ${timeoutMs} ms for ${what} (${expression})${last ? ": " + last.message : ""}`);
  }
  async screenshot(name) {
    const {data} = await this.cmd("Page.captureScreenshot", {format: "png", captureBeyondViewport: true});
    fs.writeFileSync(path.join(args.out, name), Buffer.from(data, "base64"));
  }
}

// the cause pair from warnings.csv: at the STOP's cycle, the arm's warning of smallest TTC (ties:
// the closer), as "arm/link" and its other body
function causeFromCsv(run, arm, t) {
  const rows = run.warnings.filter(w => w.arm === arm && w.t === t);
  if (!rows.length) return null;
  rows.sort((a, b) => a.ttc - b.ttc || a.d - b.d);
  return [arm + "/" + rows[0].link, rows[0].other];
}

async function check(browser, scenario, tag, extra, expect) {
  const run = runArm(scenario, tag, extra);
  const s = run.summary;
  // self-contained: nothing to fetch (the SVG namespace is a name, not a request)
  const urls = run.html.replace(/http:\/\/www\.w3\.org\/2000\/svg/g, "").match(/(https?:|\/\/[a-z0-9.-]+\/|\bsrc=|\bhref=|url\(|@import)/gi);
  if (urls) fail(`${tag}: replay.html refers outside itself: ${urls.slice(0, 5).join(" ")}`);
  const bytes = Buffer.byteLength(run.html);
  if (bytes > 4e6) fail(`${tag}: replay.html is ${bytes} bytes, more than 4 MB`);
  const csvStops = run.warnings.filter(w => w.stop).length;
  if (csvStops !== s.stops) fail(`${tag}: warnings.csv has ${csvStops} STOP rows, summary.json ${s.stops} stops`);
  if (expect.stops !== undefined && s.stops !== expect.stops) fail(`${tag}: ${s.stops} STOPs, the scenario's figure is ${expect.stops}`);

  const page = await browser.open("file://" + path.resolve(run.out, "replay.html"));
  await page.waitFor("window.replay && window.replay.ready", `${tag}: the page to draw`);
  const shapes = s.capsules + s.obstacles + 12 * (expect.persons || 0);
  for (const v of ["top", "side"]) {
    const n = await page.eval(`replay.shapes('${v}')`);
    if (n !== shapes) fail(`${tag}: the ${v} view draws ${n} shapes, not ${s.capsules} capsules + ${s.obstacles} obstacles + ${expect.persons || 0} persons x 12`);
  }
  // every frame holds every capsule, and every pose drawn lies inside both views
  const bad = await page.eval(`(() => { const D = replay.data, nC = D.cap_arm.length, out = [];
    const boxes = ['top', 'side'].map(id => document.getElementById(id).viewBox.baseVal);
    const inside = (p, r) => [[0, 1], [0, 2]].every(([u, w], k) => { const b = boxes[k];
      return p[u] - r >= b.x && p[u] + r <= b.x + b.width && -p[w] + r <= b.y + b.height && -p[w] - r >= b.y; });
    D.fc.forEach((f, i) => { if (f.length !== 6 * nC) out.push('frame ' + i + ' holds ' + f.length + ' numbers');
      for (let c = 0; c < nC; ++c) for (const e of [0, 3]) { const p = [f[6*c+e]/1000, f[6*c+e+1]/1000, f[6*c+e+2]/1000];
        if (!inside(p, D.cap_r[c])) out.push('frame ' + i + ' capsule ' + c + ' outside a view'); } });
    D.fp.forEach((f, i) => { for (let k = 0; k < f.length; k += 1 + 6 * D.parts.length) for (let j = 0; j < D.parts.length; ++j)
      for (const e of [0, 3]) { const q = k + 1 + 6 * j + e; if (!inside([f[q]/1000, f[q+1]/1000, f[q+2]/1000], D.part_r[j])) out.push('frame ' + i + ' person part outside a view'); } });
    return out.slice(0, 5); })()`);
  if (bad.length) fail(`${tag}: ${bad.join("; ")}`);
  const marks = await page.eval("replay.stopMarks()");
  if (marks !== s.stops) fail(`${tag}: the timeline marks ${marks} STOPs, summary.json and warnings.csv have ${s.stops}`);
  const frames = await page.eval("replay.frames()");
  const data = await page.eval("({cycles: replay.data.cycles, stride: replay.data.stride, stops: replay.data.stops, arms: replay.data.arms, ft: replay.data.ft})");
  if (data.cycles !== s.cycles) fail(`${tag}: the page says ${data.cycles} cycles, summary.json ${s.cycles}`);
  // bounded: at most 2000 regular frames, every stride-th cycle, and the STOPs' own
  if (frames > 2000 + data.stops.length) fail(`${tag}: ${frames} frames for ${s.cycles} cycles`);
  if (frames < Math.min(200, s.cycles)) fail(`${tag}: only ${frames} frames for ${s.cycles} cycles`);
  // each STOP: its frame is its cycle, and the highlighted pair is warnings.csv's
  let shot = false;
  for (let k = 0; k < data.stops.length; ++k) {
    const st = data.stops[k];
    const arm = data.arms[st.a];
    await page.eval(`replay.seek(${st.f})`);
    const ft = data.ft[st.f];
    if (ft !== st.t) fail(`${tag}: STOP ${k + 1} of ${arm} at ${st.t} s is shown at ${ft} s`);
    const csvRow = run.warnings.find(w => w.arm === arm && w.stop && +w.t === st.t);
    if (!csvRow) fail(`${tag}: STOP ${k + 1} of ${arm} at ${st.t} s has no STOP row in warnings.csv`);
    const want = causeFromCsv(run, arm, csvRow.t);
    if (st.body !== want[0] || st.other !== want[1])
      fail(`${tag}: STOP ${k + 1} of ${arm} at ${st.t} s: the page's cause ${st.body} - ${st.other}, warnings.csv's ${want.join(" - ")}`);
    for (const v of ["top", "side"]) {
      const lit = await page.eval(`replay.highlighted('${v}')`);
      for (const name of want)
        if (!lit.includes(name)) fail(`${tag}: STOP ${k + 1} of ${arm}: ${name} is not highlighted in the ${v} view (${lit.join(", ")})`);
    }
    if (!shot) {
      await page.screenshot(`${tag}_stop.png`);
      shot = true;
    }
  }
  if (expect.persons) {
    // a frame with the person present: 12 parts visible in each view
    const seen = await page.eval(`(() => { for (let f = 0; f < replay.frames(); ++f) if (replay.data.fp[f].length) { replay.seek(f);
      return Array.from(document.querySelectorAll('#top .shape.person')).filter(e => e.getAttribute('visibility') === 'visible').length; } return 0; })()`);
    if (seen !== 12 * expect.persons) fail(`${tag}: ${seen} person parts visible, not ${12 * expect.persons}`);
    if (!shot) await page.screenshot(`${tag}.png`);
  }
  // play a second of it: the animation runs without an error
  await page.eval("document.getElementById('speed').value = '4'; document.getElementById('play').click()");
  await sleep(1000);
  if (browser.exceptions.length) fail(`${tag}: the page threw: ${browser.exceptions.join("; ")}`);
  const own = "file://" + path.resolve(run.out, "replay.html");
  const foreign = browser.requests.filter(u => u !== own && u !== "about:blank");
  if (foreign.length) fail(`${tag}: the page asked for ${foreign.join(", ")}`);
  browser.requests.length = 0;
  console.log(`arm_replay_test: ${tag}: ${shapes} shapes in each view, ${marks} STOPs = summary.json = warnings.csv, ` +
              `${data.stops.length} cause pairs = warnings.csv's, ${frames} frames of ${s.cycles} cycles (every ${data.stride}), ` +
              `${(bytes / 1e6).toFixed(2)} MB`);
}

(async () => {
  const browser = new Browser();
  await browser.send("Target.getTargets");  // the pipe answers: the browser is up
  await check(browser, "two_pandas.yaml", "two_pandas", [], {stops: 2});
  await check(browser, "iiwa_truss.yaml", "iiwa_truss_open", ["--open-loop"], {});
  await check(browser, "person_walkup.yaml", "person_walkup", [], {persons: 1});
  browser.proc.kill("SIGKILL");
  clearTimeout(overall);
  console.log(`arm_replay_test: OK (screenshots in ${args.out})`);
  process.exit(0);
})().catch(e => fail(e.stack || String(e)));
