// Screenshots of a suite's report.html and of its first run's page (failing runs come first), taken
// with the same headless chromium and playwright-core as the report's test: the figures of
// docs/REPORTS.md.
//
//   node tests/report/screenshots.mjs SUITE_OUT FIGURE_DIR
//
// writes FIGURE_DIR/report_suite.png (the top), report_charts.png (the pass rates and the time
// chart) and report_run.png (the first run's page), 1280 px wide.
import { existsSync } from "node:fs";
import { join } from "node:path";
import { pathToFileURL } from "node:url";
import { chromium } from "playwright-core";

const [suite, figures] = process.argv.slice(2);
if (!suite || !figures || !existsSync(join(suite, "report.html"))) {
  console.error("usage: node tests/report/screenshots.mjs SUITE_OUT FIGURE_DIR (SUITE_OUT holds report.html)");
  process.exit(2);
}
const browser = await chromium.launch({ executablePath: process.env.OVPC_CHROMIUM || "/usr/bin/chromium", args: ["--no-sandbox"] });
const page = await browser.newPage({ viewport: { width: 1280, height: 1100 } });
await page.goto(pathToFileURL(join(suite, "report.html")).href);
await page.screenshot({ path: join(figures, "report_suite.png") });
await page.setViewportSize({ width: 1280, height: 900 });
await page.locator("#time_chart").scrollIntoViewIfNeeded();
await page.screenshot({ path: join(figures, "report_charts.png") });
await page.locator("#runs tbody tr a").first().click();
await page.waitForLoadState("load");
await page.setViewportSize({ width: 1280, height: 1500 });
await page.screenshot({ path: join(figures, "report_run.png") });
await browser.close();
console.log(`wrote report_suite.png, report_charts.png and report_run.png in ${figures}`);
