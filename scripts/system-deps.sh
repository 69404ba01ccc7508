#!/usr/bin/env bash
# Debian packages some tests use, installed when running as root with apt-get (as CI does).
# Elsewhere, or when apt-get fails, nothing is installed and the tests that need them skip,
# each saying why.
set -euo pipefail
# package -> why the tests need it
declare -A WHY=(
    [gcc-arm-none-eabi]="Cortex-M4F cross-compiler: flash, RAM and emulated instructions of the exported C (tests/test_deploy_*.py, test_search_budget.py)"
    [libnewlib-arm-none-eabi]="the C library the Cortex-M4F builds link against"
    [postgresql]="a local PostgreSQL server for the shared Optuna study (tests/test_search_postgres.py)"
)
missing=()
for pkg in gcc-arm-none-eabi libnewlib-arm-none-eabi postgresql; do
    dpkg -s "$pkg" >/dev/null 2>&1 || missing+=("$pkg")
done
if [ ${#missing[@]} -eq 0 ]; then
    echo "system-deps: gcc-arm-none-eabi, libnewlib-arm-none-eabi, postgresql already installed"
    exit 0
fi
if [ "$(id -u)" -eq 0 ] && command -v apt-get >/dev/null; then
    echo "system-deps: installing as root with apt-get:"
    for pkg in "${missing[@]}"; do echo "  $pkg: ${WHY[$pkg]}"; done
    if ! { apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq "${missing[@]}" >/dev/null; }; then
        echo "system-deps: apt-get could not install ${missing[*]}: the tests needing them will skip" >&2
    fi
else
    echo "system-deps: not root (or no apt-get): ${missing[*]} not installed; the tests needing them will skip" >&2
    for pkg in "${missing[@]}"; do echo "  $pkg: ${WHY[$pkg]}" >&2; done
fi
