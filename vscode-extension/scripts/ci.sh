#!/usr/bin/env bash
# CI for the VS Code extension: install, static checks and unit tests, package, end-to-end test
# in a real VS Code (code-server + headless Chromium). Needs node 20+, npm, and the rdcd Python
# package installed (rdcd-lsp on PATH, or RDCD_E2E_PYTHON set to an interpreter that has it).
set -euo pipefail
cd "$(dirname "$0")/.."
# test:e2e caches code-server, its node and playwright-core in $RDCD_E2E_DIR (default
# ~/.cache/rdcd-e2e), outside the checkout, so that fresh clones reuse them.
npm ci --no-audit --no-fund
npm test
npm run package
npm run test:e2e -- --no-package
