#!/usr/bin/env bash
# CI step for the replay viewer (run from .ci/run after pytest):
# 1. the committed bundle sim/replay/viewer.js must be exactly what its source builds to with the
#    locked packages (package-lock.json), so the page Python users get is the reviewed source;
# 2. the replay's browser tests must run in real headless Chromium, not skip.
set -euo pipefail
cd "$(dirname "$0")"
npm ci --no-audit --no-fund >/dev/null
fresh=$(mktemp --suffix=.js)
trap 'rm -f "$fresh"' EXIT
node build.mjs "$fresh"
if ! cmp -s "$fresh" ../viewer.js; then
  echo "sim/replay/viewer.js differs from a fresh build of sim/replay/viewer/src:" >&2
  echo "run 'npm ci && npm run build' in sim/replay/viewer and commit sim/replay/viewer.js" >&2
  exit 1
fi
cmp -s node_modules/three/LICENSE ../THREE_LICENSE || { echo "sim/replay/THREE_LICENSE is not three's licence" >&2; exit 1; }
if ! command -v "${CHROMIUM:-/usr/bin/chromium}" >/dev/null; then
  (apt-get update -qq && apt-get install -y -qq chromium) >/dev/null
fi
cd ../../..
RDCD_REPLAY_BROWSER=require python -m pytest -q tests/replay/test_browser.py
