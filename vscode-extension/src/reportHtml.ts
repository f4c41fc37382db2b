// Renders the simulation report (sim/report.py, read by simulateArgs.ts) as the HTML of the result
// view: its scalar figures as the summary, the modules with their final roles, the fragment sizes,
// and the whole report as JSON. No `vscode` import: unit-tested.
import { isRecord, type ReportModule, type SimulationReport } from "./simulateArgs";

export interface ReportView {
  readonly report: SimulationReport;
  /** The webview URI of the trajectory plot, if there is one. */
  readonly plotSrc?: string | undefined;
  /** The webview's CSP source (webview.cspSource). */
  readonly cspSource: string;
  /** The name of the simulated file. */
  readonly fileName: string;
}

export function escapeHtml(text: string): string {
  return text
    .replace(/&/g, "&amp;")
    .replace(/</g, "&lt;")
    .replace(/>/g, "&gt;")
    .replace(/"/g, "&quot;")
    .replace(/'/g, "&#39;");
}

function isScalar(value: unknown): value is string | number | boolean | null {
  return value === null || ["string", "number", "boolean"].includes(typeof value);
}

/** A short human text for any value. */
export function formatValue(value: unknown): string {
  if (value === null || value === undefined) {
    return "—";
  }
  if (typeof value === "number") {
    return Number.isInteger(value) ? String(value) : String(Math.round(value * 1000) / 1000);
  }
  if (typeof value === "string") {
    return value;
  }
  if (typeof value === "boolean") {
    return value ? "yes" : "no";
  }
  if (Array.isArray(value) && value.every((item) => isScalar(item))) {
    return value.map((item) => formatValue(item)).join(", ");
  }
  return JSON.stringify(value);
}

function humanize(key: string): string {
  const spaced = key.replace(/_/g, " ").replace(/([a-z])([A-Z])/g, "$1 $2");
  return spaced.charAt(0).toUpperCase() + spaced.slice(1);
}

/** The summary: the report's scalar fields, short lists of scalars and small records of scalars. */
export function summaryEntries(report: SimulationReport): [string, string][] {
  const entries: [string, string][] = [];
  for (const [key, value] of Object.entries(report)) {
    if (isScalar(value) || (Array.isArray(value) && value.length <= 8 && value.every((item) => isScalar(item)))) {
      entries.push([humanize(key), formatValue(value)]);
    } else if (isRecord(value) && Object.keys(value).length <= 6 && Object.values(value).every((item) => isScalar(item))) {
      entries.push([humanize(key), Object.entries(value).map(([name, item]) => `${name} ${formatValue(item)}`).join(", ")]);
    }
  }
  return entries;
}

/** `name: value` pairs of what the report says of a module besides its id and final role; long lists only counted. */
function moduleDetails(module: ReportModule): string {
  return Object.entries(module)
    .filter(([name, value]) => name !== "id" && name !== "final_role" && !(Array.isArray(value) && value.length === 0))
    .map(([name, value]) => {
      if (Array.isArray(value) && (value.length > 4 || !value.every((item) => isScalar(item)))) {
        return `${name}: ${value.length} ${value.length === 1 ? "entry" : "entries"}`;
      }
      return `${name}: ${formatValue(value)}`;
    })
    .join("; ");
}

export interface ModuleRow {
  readonly module: string;
  readonly role: string;
  readonly details: string;
}

/** One row per module: its id, its final role, and the rest of what the report says of it. */
export function moduleRows(report: SimulationReport): ModuleRow[] {
  return report.modules.map((module) => ({
    module: formatValue(module.id),
    role: module.final_role ?? "(none)",
    details: moduleDetails(module),
  }));
}

function table(headers: readonly string[], rows: readonly (readonly string[])[], cls: string): string {
  const head = headers.map((header) => `<th>${escapeHtml(header)}</th>`).join("");
  const body = rows
    .map((row) => `<tr>${row.map((cell) => `<td>${escapeHtml(cell)}</td>`).join("")}</tr>`)
    .join("\n");
  return `<table class="${cls}"><thead><tr>${head}</tr></thead><tbody>\n${body}\n</tbody></table>`;
}

/** The report with every list longer than `limit` cut down to its first entries and a count. */
export function shorten(value: unknown, limit = 20): unknown {
  if (Array.isArray(value)) {
    const items = (value as unknown[]).slice(0, limit).map((item) => shorten(item, limit));
    return value.length > limit ? [...items, `… ${value.length - limit} more`] : items;
  }
  if (isRecord(value)) {
    return Object.fromEntries(Object.entries(value).map(([key, item]) => [key, shorten(item, limit)]));
  }
  return value;
}

/** The sections of the result view: the plot, the summary, the roles, the fragments, the raw report. */
export function reportSections(view: Pick<ReportView, "report" | "plotSrc">): string {
  const { report } = view;
  const sections: string[] = [];

  sections.push(
    `<section id="plot"><h2>Trajectory</h2>${
      view.plotSrc !== undefined
        ? `<img id="trajectory" src="${escapeHtml(view.plotSrc)}" alt="Trajectory plot of the simulated robot">`
        : "<p>The simulation produced no plot.</p>"
    }</section>`,
  );

  const summary = summaryEntries(report);
  sections.push(
    `<section id="summary"><h2>Summary</h2>${
      summary.length > 0 ? table(["", ""], summary, "summary") : "<p>The report has no summary.</p>"
    }</section>`,
  );

  const modules = moduleRows(report);
  sections.push(
    `<section id="roles"><h2>Roles per module</h2>${
      modules.length > 0
        ? table(["Module", "Role", "Details"], modules.map((row) => [row.module, row.role, row.details]), "roles")
        : "<p>The report lists no modules.</p>"
    }</section>`,
  );

  sections.push(
    `<section id="fragments"><h2>Fragment sizes</h2>${
      report.fragments.length > 0
        ? table(["Fragment", "Bytes"], report.fragments.map((fragment) => [fragment.name, formatValue(fragment.size)]), "fragments")
        : "<p>The report lists no fragments.</p>"
    }</section>`,
  );

  sections.push(
    `<section id="raw"><details><summary>Full report (JSON, long lists shortened)</summary><pre>${escapeHtml(
      JSON.stringify(shorten(report), null, 2),
    )}</pre></details></section>`,
  );
  return sections.join("\n");
}

/** The report's style sheet, its rules scoped to the element `scope` (a selector). */
export function reportStyle(scope: string): string {
  return `${scope} { font-family: var(--vscode-font-family); color: var(--vscode-foreground); padding: 0 1em 2em; }
${scope} h1 { font-size: 1.4em; } ${scope} h2 { font-size: 1.15em; margin-top: 1.4em; } ${scope} h3 { font-size: 1em; }
${scope} table { border-collapse: collapse; margin: 0.4em 0; }
${scope} th, ${scope} td { text-align: left; padding: 0.2em 0.8em 0.2em 0; border-bottom: 1px solid var(--vscode-panel-border, #8884); vertical-align: top; }
${scope} table.summary thead { display: none; }
${scope} img#trajectory { max-width: 100%; background: white; border: 1px solid var(--vscode-panel-border, #8884); }
${scope} pre { white-space: pre-wrap; font-family: var(--vscode-editor-font-family); font-size: 0.9em; }`;
}

/** The whole HTML page of the result view (no scripts; images only from the webview source). */
export function renderReportHtml(view: ReportView): string {
  const csp = [
    "default-src 'none'",
    `img-src ${view.cspSource} data:`,
    `style-src ${view.cspSource} 'unsafe-inline'`,
  ].join("; ");
  return `<!DOCTYPE html>
<html lang="en">
<head>
<meta charset="UTF-8">
<meta http-equiv="Content-Security-Policy" content="${csp}">
<meta name="viewport" content="width=device-width, initial-scale=1.0">
<title>RDCD simulation: ${escapeHtml(view.fileName)}</title>
<style>
${reportStyle("body")}
</style>
</head>
<body>
<h1>RDCD simulation: ${escapeHtml(view.fileName)}</h1>
${reportSections(view)}
</body>
</html>
`;
}

/** The page shown when the simulation failed. */
export function renderErrorHtml(fileName: string, message: string, cspSource: string): string {
  return `<!DOCTYPE html>
<html lang="en"><head><meta charset="UTF-8">
<meta http-equiv="Content-Security-Policy" content="default-src 'none'; style-src ${cspSource} 'unsafe-inline'">
<title>RDCD simulation: ${escapeHtml(fileName)}</title>
<style>
body { font-family: var(--vscode-font-family); color: var(--vscode-foreground); padding: 0 1em 2em; }
h1 { font-size: 1.4em; }
pre { white-space: pre-wrap; font-family: var(--vscode-editor-font-family); color: var(--vscode-errorForeground); }
</style></head>
<body><h1>RDCD simulation: ${escapeHtml(fileName)}</h1>
<p class="error">The simulation failed:</p><pre>${escapeHtml(message)}</pre></body></html>
`;
}
