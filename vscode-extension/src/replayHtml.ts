// The Simulate panel with the replay: the page of `rdcd simulate --replay` (sim/replay/page.py)
// shown as the webview's own document, so that its script can post "reveal this line" through
// acquireVsCodeApi(), with a tab bar and the report (summary, plot, roles) added. The page's own
// Content-Security-Policy stays: it allows its inline script and style by hash and nothing remote;
// this adds only a nonce for the tab bar's style and the webview's source for the plot image. The
// tabs are radio buttons and CSS: no script of ours. No `vscode` import: unit-tested.
import { escapeHtml, reportSections, reportStyle } from "./reportHtml";
import type { SimulationReport } from "./simulateArgs";

export interface ReplayView {
  /** The replay page as the simulator wrote it. */
  readonly page: string;
  readonly report: SimulationReport;
  /** The webview URI of the trajectory plot, if there is one. */
  readonly plotSrc?: string | undefined;
  /** The webview's CSP source (webview.cspSource), for the plot. */
  readonly cspSource: string;
  readonly fileName: string;
  /** A fresh random nonce (base64) for the style this adds. */
  readonly nonce: string;
}

const META = /<meta\s+http-equiv="Content-Security-Policy"\s+content="([^"]*)"\s*\/?>/i;

function unescapeAttribute(text: string): string {
  return text
    .replace(/&quot;/g, '"')
    .replace(/&#x27;|&#39;/g, "'")
    .replace(/&lt;/g, "<")
    .replace(/&gt;/g, ">")
    .replace(/&amp;/g, "&");
}

export type Policy = Map<string, string[]>;

/** The directives of a Content-Security-Policy, in their order. */
export function parsePolicy(text: string): Policy {
  const policy: Policy = new Map();
  for (const part of text.split(";")) {
    const [name, ...sources] = part.trim().split(/\s+/);
    if (name !== undefined && name !== "" && !policy.has(name.toLowerCase())) {
      policy.set(name.toLowerCase(), sources);
    }
  }
  return policy;
}

export function formatPolicy(policy: Policy): string {
  return [...policy].map(([name, sources]) => [name, ...sources].join(" ")).join("; ");
}

// What a replay page may allow: its own inline code by hash or nonce, data: and blob: URLs.
const LOCAL_SOURCE = /^('none'|'(sha256|sha384|sha512)-[A-Za-z0-9+/=_-]+'|'nonce-[A-Za-z0-9+/=_-]+'|data:|blob:)$/;

/** Why the page's policy is not strict and local-only, or undefined when it is. */
export function policyProblem(policy: Policy): string | undefined {
  const fallback = policy.get("default-src");
  if (fallback === undefined || fallback.join(" ") !== "'none'") {
    return "its policy does not start from default-src 'none'";
  }
  for (const [name, sources] of policy) {
    const bad = sources.find((source) => !LOCAL_SOURCE.test(source));
    if (bad !== undefined) {
      return `its policy allows ${bad} in ${name}`;
    }
  }
  return undefined;
}

/** The webview's source(s) as CSP source expressions (cspSource may hold several). */
function sourcesOf(cspSource: string): string[] {
  return cspSource.split(/\s+/).filter((source) => source !== "");
}

/** The page's policy with the nonce'd style and the plot's source added. */
export function embeddedPolicy(policy: Policy, nonce: string, cspSource: string): Policy {
  const result: Policy = new Map([...policy].map(([name, sources]) => [name, [...sources]]));
  const add = (name: string, sources: string[]) => {
    const current = (result.get(name) ?? []).filter((source) => source !== "'none'");
    result.set(name, [...current, ...sources.filter((source) => !current.includes(source))]);
  };
  add("style-src", [`'nonce-${nonce}'`]);
  add("img-src", sourcesOf(cspSource));
  return result;
}

const TABS_STYLE = `
:root { --rdcd-tabs-height: 30px; }
body { padding: 0; } /* the webview's default style pads the body; the replay fills the panel */
#rdcd-tabs { box-sizing: border-box; height: var(--rdcd-tabs-height); display: flex; align-items: stretch; gap: 2px; padding: 0 8px;
  font: 13px var(--vscode-font-family, system-ui, sans-serif); color: var(--vscode-foreground, #ccc);
  background: var(--vscode-editorGroupHeader-tabsBackground, #252526); border-bottom: 1px solid var(--vscode-panel-border, #8884); }
#rdcd-tabs input { position: absolute; opacity: 0; width: 1px; height: 1px; margin: 0; }
#rdcd-tabs label { display: flex; align-items: center; padding: 0 12px; cursor: pointer; border-bottom: 2px solid transparent; white-space: nowrap; }
#rdcd-tabs input:checked + label { border-bottom-color: var(--vscode-focusBorder, #0078d4); font-weight: 600; }
#rdcd-tabs input:focus-visible + label { outline: 1px solid var(--vscode-focusBorder, #0078d4); outline-offset: -1px; }
#rdcd-tabs .rdcd-hint { margin-left: auto; align-self: center; opacity: 0.7; font-size: 12px; min-width: 0;
  white-space: nowrap; overflow: hidden; text-overflow: ellipsis; }
.rr-root { height: calc(100vh - var(--rdcd-tabs-height)) !important; }
@media (max-width: 760px) { .rr-root { grid-template-columns: 1fr 250px !important; } } /* a panel beside the editor */
#rdcd-report { display: none; position: fixed; top: var(--rdcd-tabs-height); left: 0; right: 0; bottom: 0; overflow: auto; z-index: 10;
  background: var(--vscode-editor-background, #1e1e1e); }
body:has(#rdcd-tab-report:checked) #rdcd-report { display: block; }
`;

/** The tab bar and the report, put first in the page's body (the replay builds its layout after them). */
function addedBody(view: ReplayView): string {
  return `<div id="rdcd-tabs" role="radiogroup" aria-label="Simulation views">
<input type="radio" name="rdcd-tab" id="rdcd-tab-replay" checked><label for="rdcd-tab-replay">Replay</label>
<input type="radio" name="rdcd-tab" id="rdcd-tab-report"><label for="rdcd-tab-report">Summary and plot</label>
<span class="rdcd-hint">Click an event to show its line in the editor</span>
</div>
<div id="rdcd-report"><h1>RDCD simulation: ${escapeHtml(view.fileName)}</h1>
${reportSections(view)}
</div>
`;
}

/** Thrown when the replay page cannot be shown in the panel; its message says why. */
export class ReplayPageError extends Error {}

/** The webview's HTML: the replay page with its policy extended, the tab bar and the report. */
export function renderReplayHtml(view: ReplayView): string {
  if (!/^[A-Za-z0-9+/=]{16,}$/.test(view.nonce)) {
    throw new ReplayPageError("the nonce must be at least 16 base64 characters");
  }
  const meta = META.exec(view.page);
  if (meta === null || meta[1] === undefined) {
    throw new ReplayPageError("the replay page has no Content-Security-Policy");
  }
  if (META.exec(view.page.slice(meta.index + meta[0].length)) !== null) {
    throw new ReplayPageError("the replay page has more than one Content-Security-Policy");
  }
  const policy = parsePolicy(unescapeAttribute(meta[1]));
  const problem = policyProblem(policy);
  if (problem !== undefined) {
    throw new ReplayPageError(`the replay page is not local-only: ${problem}`);
  }
  const head = view.page.search(/<\/head>/i);
  const body = /<body[^>]*>/i.exec(view.page);
  if (head === -1 || body === null || body.index < head || meta.index > head) {
    throw new ReplayPageError("the replay page has no <head> with the policy followed by a <body>");
  }
  const newMeta = `<meta http-equiv="Content-Security-Policy" content="${escapeHtml(
    formatPolicy(embeddedPolicy(policy, view.nonce, view.cspSource)),
  )}">`;
  const style = `<style nonce="${view.nonce}">${TABS_STYLE}\n${reportStyle("#rdcd-report")}\n</style>\n`;
  const bodyEnd = body.index + body[0].length;
  return (
    view.page.slice(0, meta.index) +
    newMeta +
    view.page.slice(meta.index + meta[0].length, head) +
    style +
    view.page.slice(head, bodyEnd) +
    "\n" +
    addedBody(view) +
    view.page.slice(bodyEnd)
  );
}

/**
 * The zero-based line to reveal for a message from the replay (`{type: "revealLine", line}`, line
 * one-based as the replay shows it), or undefined for any other message or a line the document lacks.
 */
export function revealedLine(message: unknown, lineCount: number): number | undefined {
  if (typeof message !== "object" || message === null || Array.isArray(message)) {
    return undefined;
  }
  const { type, line } = message as Record<string, unknown>;
  if (type !== "revealLine" || typeof line !== "number" || !Number.isInteger(line) || line < 1 || line > lineCount) {
    return undefined;
  }
  return line - 1;
}
