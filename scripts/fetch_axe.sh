#!/usr/bin/env bash
# Fetch axe-core (the accessibility audit the browser tests inject into every console screen and
# the report) from the npm registry, pinned by version and SHA-256, into .cache/ (not tracked).
# The tests fail, never skip, when it is missing: run scripts/setup.sh.
set -euo pipefail
cd "$(dirname "$0")/.."
VERSION=4.14.1
SHA256=e6b0ce02b84d892e2e33e403485e7f3d6c29e2be6df65daf44d89ba564139745
DEST=".cache/axe-core-$VERSION"
if [ -f "$DEST/axe.min.js" ]; then
  exit 0
fi
mkdir -p "$DEST"
tmp=$(mktemp)
trap 'rm -f "$tmp"' EXIT
curl --proto '=https' --tlsv1.2 -sSf -o "$tmp" "https://registry.npmjs.org/axe-core/-/axe-core-$VERSION.tgz"
echo "$SHA256  $tmp" | sha256sum -c --quiet -
tar -xzf "$tmp" -C "$DEST" --strip-components=1 package/axe.min.js package/LICENSE
echo "setup: axe-core $VERSION in $DEST"
