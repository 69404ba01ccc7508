#!/usr/bin/env bash
# Debian packages the tests use. Installed when running as root with apt-get available;
# elsewhere the tests that need them skip and say why.
set -euo pipefail
# Cortex-M4F cross-compile (tests/test_deploy_*, test_search_budget); a PostgreSQL server for
# the shared-study test (tests/test_search_postgres.py)
PACKAGES=(gcc-arm-none-eabi libnewlib-arm-none-eabi postgresql)
missing=()
for pkg in "${PACKAGES[@]}"; do
    dpkg -s "$pkg" >/dev/null 2>&1 || missing+=("$pkg")
done
if [ ${#missing[@]} -eq 0 ]; then exit 0; fi
if [ "$(id -u)" -eq 0 ] && command -v apt-get >/dev/null; then
    if ! { apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq "${missing[@]}" >/dev/null; }; then
        echo "apt-get could not install ${missing[*]}: tests needing them will skip" >&2
    fi
else
    echo "not root: tests needing ${missing[*]} will skip" >&2
fi
