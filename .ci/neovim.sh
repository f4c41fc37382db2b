#!/usr/bin/env bash
# Installs Neovim (Debian's package) for tests/server/test_neovim.py, only if `nvim` is missing.
# Idempotent and never fatal: when it cannot install, it warns and exits 0 (the test then skips).
set -u
if command -v nvim >/dev/null 2>&1; then
  echo "neovim.sh: $(nvim --version | head -n 1) already installed"
  exit 0
fi
if ! command -v apt-get >/dev/null 2>&1; then
  echo "neovim.sh: WARNING: no apt-get; Neovim not installed, the Neovim LSP test will skip" >&2
  exit 0
fi
sudo=""
if [ "$(id -u)" -ne 0 ]; then
  if command -v sudo >/dev/null 2>&1 && sudo -n true 2>/dev/null; then
    sudo="sudo -n"
  else
    echo "neovim.sh: WARNING: not root and no sudo; Neovim not installed, the Neovim LSP test will skip" >&2
    exit 0
  fi
fi
export DEBIAN_FRONTEND=noninteractive
log="$(mktemp)"
if $sudo apt-get update -qq >"$log" 2>&1 &&
   $sudo apt-get install -y -qq --no-install-recommends neovim >>"$log" 2>&1 &&
   command -v nvim >/dev/null 2>&1; then
  echo "neovim.sh: installed $(nvim --version | head -n 1)"
else
  echo "neovim.sh: WARNING: apt-get could not install neovim; the Neovim LSP test will skip" >&2
  tail -n 20 "$log" >&2
fi
rm -f "$log"
exit 0
