// Opens a short suite's report.html in Debian's headless chromium (playwright-core, with its
// executablePath) and checks what a reader does: the run table has a row per run, failing runs
// first, sorts by a column, links to each run's page; a failing run's page shows its scorecard,
// diagnosis and top-down picture; no page logs an error or asks for anything off this machine.
// Run by CTest (report.browser) as `node --test`, with OVPC_BIN naming the ovpc program.
import { after, before, test } from "node:test";
import assert from "node:assert/strict";
import { spawnSync } from "node:child_process";
import { existsSync, mkdtempSync, readFileSync, rmSync, writeFileSync } from "node:fs";
import { tmpdir } from "node:os";
import { dirname, join } from "node:path";
import { fileURLToPath, pathToFileURL } from "node:url";

const here = dirname(fileURLToPath(import.meta.url));
const repo = join(here, "..", "..");
if (!existsSync(join(here, "node_modules", "playwright-core"))) {
  throw new Error(`${join(here, "node_modules")} is missing: run scripts/install-deps (it runs npm ci there)`);
}
const chromiumPath = process.env.OVPC_CHROMIUM || "/usr/bin/chromium";
if (!existsSync(chromiumPath)) throw new Error(`${chromiumPath} is missing: run scripts/install-deps (Debian's chromium)`);
const ovpc = process.env.OVPC_BIN;
if (!ovpc || !existsSync(ovpc)) throw new Error("OVPC_BIN must name the ovpc program (CTest sets it)");
const { chromium } = await import("playwright-core");

const work = mkdtempSync(join(tmpdir(), "ovpc-report-"));
const suite = join(work, "suite");
let browser, summary;
const problems = [];  // console errors, page errors, failed or off-machine requests

// Two seeds of the short flat scenario (passes) and of one with 3 s to do it in (fails).
before(async () => {
  const short = readFileSync(join(repo, "tests", "support", "short_flat.yaml"), "utf8");
  writeFileSync(join(work, "pass.yaml"), short);
  writeFileSync(join(work, "late.yaml"),
                short.replace("name: short_flat", "name: short_late").replace("time_limit_s: 8", "time_limit_s: 3")
                     .replace("max_time_s: 8", "max_time_s: 3"));
  const r = spawnSync(ovpc, ["suite", join(work, "pass.yaml"), join(work, "late.yaml"), "--seeds", "2", "--jobs", "2",
                             "--out", suite], { encoding: "utf8" });
  assert.equal(r.status, 1, `a run fails, so the suite exits 1: ${r.stdout}${r.stderr}`);
  summary = JSON.parse(readFileSync(join(suite, "summary.json"), "utf8"));
  browser = await chromium.launch({ executablePath: chromiumPath, args: ["--no-sandbox"] });
});
after(async () => {
  await browser?.close();
  rmSync(work, { recursive: true, force: true });
});

async function openPage() {
  const context = await browser.newContext();
  await context.route("**/*", (route) => {
    const url = route.request().url();
    if (url.startsWith("file:") || url.startsWith("data:")) return route.continue();
    problems.push(`asked for ${url}`);
    return route.abort();
  });
  const page = await context.newPage();
  page.on("console", (m) => { if (m.type() === "error" || m.type() === "warning") problems.push(`console: ${m.text()}`); });
  page.on("pageerror", (e) => problems.push(`page error: ${e.message}`));
  page.on("requestfailed", (q) => problems.push(`failed: ${q.url()}`));
  return page;
}

test("the run table has a row per run, failing runs first, and sorts by a column", async () => {
  const page = await openPage();
  await page.goto(pathToFileURL(join(suite, "report.html")).href);
  const rows = page.locator("#runs tbody tr");
  assert.equal(await rows.count(), summary.runs.length);
  assert.equal(await rows.count(), 4);
  const classes = await rows.evaluateAll((trs) => trs.map((tr) => tr.className));
  assert.deepEqual(classes, ["FAIL", "FAIL", "pass", "pass"]);
  assert.match(await page.locator("h1").textContent(), /2 of 4 runs passed/);
  // Sorted by seed (a number) the seeds go 1, 1, 2, 2; again, 2, 2, 1, 1.
  const seeds = () => page.locator("#runs tbody tr td:nth-child(3)").allTextContents();
  await page.locator("#runs th", { hasText: "seed" }).click();
  assert.deepEqual(await seeds(), ["1", "1", "2", "2"]);
  await page.locator("#runs th", { hasText: "seed" }).click();
  assert.deepEqual(await seeds(), ["2", "2", "1", "1"]);
  // Pass rate per scenario over its seeds, and a point per run in the time chart.
  const scenarios = await page.locator("#scenarios tbody tr").allTextContents();
  assert.equal(scenarios.length, 2);
  assert.ok(scenarios.some((t) => t.includes("short_late") && t.includes("0/2")), scenarios.join("\n"));
  assert.ok(scenarios.some((t) => t.includes("short_flat") && t.includes("2/2")), scenarios.join("\n"));
  assert.equal(await page.locator("#time_chart circle").count(), 4);
  assert.deepEqual(problems, []);
});

test("a failing run's page shows its scorecard, diagnosis, top-down picture and files", async () => {
  const page = await openPage();
  await page.goto(pathToFileURL(join(suite, "report.html")).href);
  const first = page.locator("#runs tbody tr").first();
  const index = Number(await first.locator("td").first().textContent());
  const run = summary.runs.find((r) => r.index === index);
  assert.equal(run.passed, false);
  await Promise.all([page.waitForURL(/runs\/\d+\.html$/), first.locator("a").click()]);
  assert.ok(page.url().endsWith(`runs/${index}.html`), page.url());
  assert.match(await page.locator("h1").textContent(), /short_late seed \d FAIL/);
  assert.ok((await page.locator("#scorecard tr.FAIL").count()) >= 1, "a failed criterion is shown");
  const diagnosis = await page.locator("#diagnosis").textContent();
  assert.ok(diagnosis.includes(run.result.diagnosis.summary), `the diagnosis is shown: ${diagnosis}`);
  assert.ok(diagnosis.includes(run.result.diagnosis.verdict));
  assert.ok(await page.locator("img.topdown").evaluate((img) => img.complete && img.naturalWidth > 0), "topdown.png loads");
  const files = await page.locator("#files a").allTextContents();
  for (const name of ["result.json", "topdown.png", "trajectory.csv"]) assert.ok(files.includes(name), files.join(", "));
  // A file's link opens the run's file.
  const href = await page.locator("#files a", { hasText: "result.json" }).getAttribute("href");
  assert.equal(fileURLToPath(new URL(href, page.url())), join(run.out, "result.json"));
  await Promise.all([page.waitForURL(/report\.html$/), page.locator("a", { hasText: "the suite's report" }).click()]);
  assert.deepEqual(problems, []);
});

test("the report asks for nothing off this machine", () => {
  const html = readFileSync(join(suite, "report.html"), "utf8");
  assert.doesNotMatch(html, /(src|href)="(https?:)?\/\//);
  assert.doesNotMatch(html, /@import|url\(/);
});
