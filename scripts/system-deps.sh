#!/usr/bin/env bash
# Debian packages the tests use. Installed when running as root with apt-get available;
# elsewhere the tests that need them skip and say why.
set -euo pipefail
PACKAGES=()
missing=()
for pkg in "${PACKAGES[@]}"; do
    dpkg -s "$pkg" >/dev/null 2>&1 || missing+=("$pkg")
done
if [ ${#missing[@]} -eq 0 ]; then exit 0; fi
if [ "$(id -u)" -eq 0 ] && command -v apt-get >/dev/null; then
    apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq "${missing[@]}" >/dev/null
else
    echo "not root: tests needing ${missing[*]} will skip" >&2
fi
