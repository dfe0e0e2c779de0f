#!/usr/bin/env node
// The page of `stsim pool serve` in a real browser, as a user plays it: Debian's chromium,
// headless, driven over the DevTools protocol on a pipe (--remote-debugging-pipe: JSON messages
// separated by NUL on fds 3 and 4, so no WebSocket library and nothing from npm). It loads the
// page, drags the cue from the cue ball, waits for the shot to end and checks that the events the
// page applied and the positions it shows are `stsim pool`'s for the same layout and shot; then
// moves a ball, shoots again with typed angle and speed, downloads the game and replays it with
// the CLI (the page's events again), restarts and checks the rack is back. Screenshots go to
// --out. Every wait is bounded; the server listens on 127.0.0.1 only.
//
//   node pool_page_test.js --stsim build/stsim --out DIR [--chromium /usr/bin/chromium]
"use strict";
const {spawn, spawnSync} = require("child_process");
const fs = require("fs");
const path = require("path");

const args = {chromium: "/usr/bin/chromium"};
for (let i = 2; i < process.argv.length; i += 2) args[process.argv[i].replace(/^--/, "")] = process.argv[i + 1];
if (!args.stsim || !args.out) {
  console.error("usage: pool_page_test.js --stsim STSIM --out DIR [--chromium PATH]");
  process.exit(2);
}
fs.rmSync(args.out, {recursive: true, force: true});
fs.mkdirSync(args.out, {recursive: true});
const children = [];
function fail(message) {
  console.error("pool_page_test: FAIL: " + message);
  for (const c of children) c.kill("SIGKILL");
  process.exit(1);
}
const overall = setTimeout(() => fail("took more than 120 s"), 120000);

// The layout both the server and the CLI start from: the served default (a standard rack, a
// little rolling resistance, version II).
const layout = `name: rack
table: {width: 2.54, height: 1.27}
rack: {kind: standard, gap: 2.0e-5}
friction: 0.15
until: 60
space: {kind: quadtree, decomposition_factor: 5}
`;
fs.writeFileSync(path.join(args.out, "layout.yaml"), layout);

// ---- the CLI: `stsim pool FILE --out DIR`, its events.csv as numbers (17 digits: exact)
function cliEvents(yamlFile, tag) {
  const out = path.join(args.out, tag);
  const r = spawnSync(args.stsim, ["pool", yamlFile, "--out", out], {encoding: "utf8", timeout: 60000});
  if (r.status !== 0) fail(`stsim pool ${yamlFile}: exit ${r.status}: ${r.stdout}${r.stderr}`);
  const lines = fs.readFileSync(path.join(out, "events.csv"), "utf8").trim().split("\n").slice(1);
  return lines.map(l => {
    const f = l.split(",");
    return {shot: +f[0], t: +f[1], k: f[2], b: +f[3], n: +f[4], p: [+f[6], +f[7]], v: [+f[8], +f[9]]};
  });
}
function sameEvents(page, cli, what) {
  if (page.length !== cli.length) fail(`${what}: the page applied ${page.length} events, the CLI wrote ${cli.length}`);
  for (let i = 0; i < cli.length; ++i) {
    const a = page[i], b = cli[i];
    if (a.k !== b.k || a.b !== b.b || a.t !== b.t || a.p[0] !== b.p[0] || a.p[1] !== b.p[1] || a.v[0] !== b.v[0] ||
        a.v[1] !== b.v[1])
      fail(`${what}: event ${i} differs: page ${JSON.stringify(a)} CLI ${JSON.stringify(b)}`);
  }
}
// Where each ball is at the end of the CLI's run: its last event (rest, stop), pocketed ones gone;
// a ball the shot never touched stays where it was before (`before`: the page's balls then).
function cliFinal(events, before) {
  const out = new Map();
  for (const b of before) out.set(b.h, b.p);
  for (const e of events) {
    if (e.k === "pocket") out.delete(e.b);
    else out.set(e.b, e.p);
  }
  return out;
}

// ---- the server
function startServer() {
  return new Promise((resolve) => {
    const p = spawn(args.stsim, ["pool", "serve", path.join(args.out, "layout.yaml"), "--listen", "127.0.0.1:0"],
                    {stdio: ["ignore", "pipe", "pipe"]});
    children.push(p);
    let text = "";
    p.stdout.on("data", d => {
      text += d;
      const m = text.match(/http:\/\/127\.0\.0\.1:(\d+)\//);
      if (m) resolve({proc: p, port: +m[1], output: () => text});
    });
    p.stderr.on("data", d => { text += d; });
    p.on("exit", code => fail(`stsim pool serve exited (${code}) early: ${text}`));
  });
}

// ---- the browser, over the DevTools protocol on a pipe
class Browser {
  constructor() {
    this.proc = spawn(args.chromium, [
      "--headless=new", "--remote-debugging-pipe", "--no-sandbox", "--disable-gpu", "--no-first-run",
      "--no-default-browser-check", "--disable-extensions", "--window-size=1400,800",
      `--user-data-dir=${path.join(args.out, "profile")}`, "about:blank"],
      {stdio: ["ignore", "ignore", "pipe", "pipe", "pipe"]});
    children.push(this.proc);
    this.proc.stderr.on("data", () => {});
    this.next = 1;
    this.waiting = new Map();
    this.listeners = [];
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
        } else if (m.method) {
          for (const l of this.listeners) l(m);
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
      setTimeout(() => reject(new Error(`${method}: no answer in 20 s`)), 20000).unref();
    });
  }
  async open(url) {
    const {targetId} = await this.send("Target.createTarget", {url: "about:blank"});
    const {sessionId} = await this.send("Target.attachToTarget", {targetId, flatten: true});
    const page = new Page(this, sessionId);
    await page.cmd("Page.enable");
    await page.cmd("Runtime.enable");
    await page.cmd("Emulation.setDeviceMetricsOverride", {width: 1400, height: 800, deviceScaleFactor: 1, mobile: false});
    await this.send("Browser.setDownloadBehavior",
                    {behavior: "allow", downloadPath: path.resolve(args.out, "downloads"), eventsEnabled: true});
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
  async waitFor(expression, what, timeoutMs = 20000) {
    const end = Date.now() + timeoutMs;
    while (Date.now() < end) {
      try { if (await this.eval(expression)) return; } catch (e) { /* the page is still loading */ }
      await sleep(50);
    }
    fail(`waited ${timeoutMs} ms for ${what} (${expression})`);
  }
  async mouse(type, xy, buttons) {
    await this.cmd("Input.dispatchMouseEvent", {type, x: xy[0], y: xy[1], button: "left", buttons, clickCount: 1});
  }
  // A drag as a hand does it: press, move in steps, release.
  async drag(from, to, steps = 12) {
    await this.mouse("mousePressed", from, 1);
    for (let i = 1; i <= steps; ++i)
      await this.mouse("mouseMoved", [from[0] + (to[0] - from[0]) * i / steps, from[1] + (to[1] - from[1]) * i / steps], 1);
    await this.mouse("mouseReleased", to, 0);
  }
  async click(selector) {
    const r = await this.eval(`(() => { const b = document.querySelector(${JSON.stringify(selector)}).getBoundingClientRect();
      return [b.left + b.width / 2, b.top + b.height / 2]; })()`);
    await this.mouse("mousePressed", r, 1);
    await this.mouse("mouseReleased", r, 0);
  }
  async screenshot(name) {
    const {data} = await this.cmd("Page.captureScreenshot", {format: "png"});
    fs.writeFileSync(path.join(args.out, name), Buffer.from(data, "base64"));
  }
}
const sleep = ms => new Promise(r => setTimeout(r, ms));

// Waits for the shot the page is showing to end; returns the events it applied.
async function shotEnds(page, index) {
  await page.waitFor(`window.lastShotEnd && window.lastShotEnd.index === ${index} && !pool.playing()`, `shot ${index} to end`, 60000);
  return page.eval("pool.applied().map(e => ({k: e.k, b: e.b, t: e.t, p: e.p, v: e.v}))");
}
function sameShown(shown, final, what) {
  if (shown.length !== final.size) fail(`${what}: the page shows ${shown.length} balls, the CLI ends with ${final.size}`);
  for (const b of shown) {
    const p = final.get(b.h);
    if (!p || p[0] !== b.p[0] || p[1] !== b.p[1]) fail(`${what}: ball ${b.n} shown at ${b.p}, the CLI has it at ${p}`);
  }
}

(async () => {
  const server = await startServer();
  const browser = new Browser();
  await browser.send("Target.getTargets");  // the pipe answers: the browser is up
  const page = await browser.open(`http://127.0.0.1:${server.port}/`);
  await page.waitFor("window.pool && pool.state() && document.getElementById('status').textContent.includes('ready')", "the page's first state");
  const rack = await page.eval("pool.shown()");
  if (rack.length !== 16) fail(`the page shows ${rack.length} balls, not the rack's 16`);
  await page.screenshot("1_rack.png");

  // 1. drag the cue back from the cue ball (the ball leaves opposite to the drag) and release
  await page.eval("document.getElementById('rate').value = '4'; document.getElementById('rate').dispatchEvent(new Event('change'))");
  const cue = rack.find(b => b.n === 0);
  const from = await page.eval(`pool.toScreen(${cue.p[0]}, ${cue.p[1]})`);
  const to = await page.eval(`pool.toScreen(${cue.p[0] - 0.65}, ${cue.p[1] - 0.004})`);
  await page.drag(from, to);
  await page.waitFor("pool.playing()", "the break to start");
  await sleep(700);
  await page.screenshot("2_break_playing.png");
  const applied1 = await shotEnds(page, 0);
  await page.screenshot("3_break_rest.png");
  // the truth: the CLI on the same layout and the velocity the server took from the drag
  const v1 = await page.eval("window.lastShot.velocity");
  fs.writeFileSync(path.join(args.out, "break.yaml"),
                   layout + `shots:\n  - {ball: 0, velocity: [${v1[0]}, ${v1[1]}]}\n`);
  const cli1 = cliEvents(path.join(args.out, "break.yaml"), "cli_break");
  sameEvents(applied1, cli1, "the break");
  sameShown(await page.eval("pool.shown()"), cliFinal(cli1, rack), "after the break");
  console.log(`pool_page_test: break by drag at ${Math.hypot(...v1).toFixed(3)} m/s: ${applied1.length} events on the page equal the CLI's, positions too`);

  // 2. move a ball (the cue ball if it is on the table, else the lowest) to a free spot and shoot it
  //    again with typed angle and speed
  const before = await page.eval("pool.shown()");
  const mover = before.find(b => b.n === 0) || before[0];
  const spot = [0.4, 0.3];
  for (const b of before) if (b !== mover && Math.hypot(b.p[0] - spot[0], b.p[1] - spot[1]) < 0.06) fail("the spot is taken; pick another");
  await page.eval("document.getElementById('tool').value = 'move'");
  await page.drag(await page.eval(`pool.toScreen(${mover.p[0]}, ${mover.p[1]})`), await page.eval(`pool.toScreen(${spot[0]}, ${spot[1]})`));
  await page.waitFor(`pool.state().balls.some(b => b.n === ${mover.n} && Math.abs(b.p[0] - ${spot[0]}) < 0.01 && Math.abs(b.p[1] - ${spot[1]}) < 0.01)`,
                     "the moved ball's new state");
  await page.screenshot("4_moved.png");
  await page.eval(`document.getElementById('tool').value = 'cue';
    document.getElementById('angle').value = '35'; document.getElementById('speed').value = '3.5'`);
  if (mover.n !== 0) fail("the break pocketed the cue ball; the typed shot strikes ball 0");
  const beforeShot2 = await page.eval("pool.shown()");
  await page.click("#shoot");
  await page.waitFor("pool.playing()", "the second shot to start");
  const applied2 = await shotEnds(page, 1);
  await page.screenshot("5_second_shot.png");

  // 3. download the game as a user does (the button; the browser saves the file) and replay it
  await page.click("#download");
  const saved = path.join(args.out, "downloads", "pool-game.yaml");
  for (let i = 0; i < 100 && !fs.existsSync(saved); ++i) await sleep(50);
  if (!fs.existsSync(saved)) fail("the download did not arrive");
  const yaml = fs.readFileSync(saved, "utf8");
  if (!/shots:/.test(yaml)) fail("the download has no shots");
  const cli2 = cliEvents(saved, "cli_download");
  // the download starts at the move (an edit starts a new layout): its one shot is the page's second
  sameEvents(applied2, cli2, "the shot after the move, replayed from the download");
  sameShown(await page.eval("pool.shown()"), cliFinal(cli2, beforeShot2), "after the second shot");
  console.log(`pool_page_test: moved ball ${mover.n}, typed shot: ${applied2.length} events equal the download's replay by the CLI`);

  // 4. restart: the rack is back, where it was at the start
  await page.click("#restart");
  await page.waitFor("pool.state().layout_shots === 0 && pool.state().balls.length === 16", "the rack after Restart");
  const again = await page.eval("pool.shown()");
  for (const b of rack) {
    const a = again.find(x => x.n === b.n);
    if (!a || a.p[0] !== b.p[0] || a.p[1] !== b.p[1]) fail(`after Restart ball ${b.n} is at ${a && a.p}, not ${b.p}`);
  }
  await page.screenshot("6_restart.png");
  console.log("pool_page_test: Restart brings the rack back");

  // a bad drag (a ball moved off the table) is refused by name and the game goes on
  await page.eval("document.getElementById('tool').value = 'move'");
  const one = again.find(b => b.n === 1);
  await page.drag(await page.eval(`pool.toScreen(${one.p[0]}, ${one.p[1]})`), await page.eval("pool.toScreen(2.6, 1.3)"));
  await page.waitFor("window.lastError && window.lastError.field === 'position'", "the error for a ball off the table");
  await page.waitFor(`pool.state().balls.find(b => b.n === 1).p[0] === ${one.p[0]}`, "ball 1 back where it was");

  // Ctrl-C stops the server cleanly
  server.proc.removeAllListeners("exit");
  const stopped = new Promise(r => server.proc.on("exit", (code, sig) => r({code, sig})));
  server.proc.kill("SIGINT");
  const {code} = await stopped;
  if (code !== 130) fail(`stsim pool serve exited ${code} on SIGINT, not 130: ${server.output()}`);
  browser.proc.kill("SIGKILL");
  clearTimeout(overall);
  console.log(`pool_page_test: OK (screenshots in ${args.out})`);
  process.exit(0);
})().catch(e => fail(e.stack || String(e)));
