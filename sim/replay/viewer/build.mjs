// Builds the replay viewer bundle that sim/replay/page.py inlines: `npm run build` writes
// ../viewer.js (committed as package data, so Python users need no Node); `node build.mjs OUT`
// writes elsewhere (ci.sh compares the two).
import { build } from "esbuild";

await build({
  entryPoints: ["src/main.js"],
  bundle: true,
  minify: true,
  format: "iife",
  target: "es2020",
  legalComments: "eof", // three.js's licence notice stays in the page
  outfile: process.argv[2] ?? "../viewer.js",
  logLevel: "warning",
});
