// Reads the server's answer to rdcd.showBytecode. No `vscode` import: unit-tested.

/** The listing text: the answer itself, or its `listing`/`text` field. */
export function listingText(result: unknown): string {
  if (typeof result === "string") {
    return result;
  }
  if (typeof result === "object" && result !== null) {
    const record = result as Record<string, unknown>;
    for (const key of ["listing", "text", "bytecode"]) {
      const value = record[key];
      if (typeof value === "string") {
        return value;
      }
    }
    return JSON.stringify(result, null, 2);
  }
  return "; The language server returned no listing.\n";
}
