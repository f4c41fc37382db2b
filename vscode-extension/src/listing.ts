// Reads the server's answer to rdcd.showBytecode. No `vscode` import: unit-tested.

/** The listing text: the server answers with the listing itself, a string (server/commands.py). */
export function listingText(result: unknown): string {
  if (typeof result !== "string") {
    throw new Error("The language server returned no listing.");
  }
  return result;
}
