#!/usr/bin/env bash
# The whole test suite, from a fresh clone: installs the package with its test extras, then runs
# the Rust checks (format, clippy with warnings as errors, tests) and the Python ones (ruff, mypy over
# the package, the tests and the benchmarks as pyproject.toml configures it, pytest).
set -euo pipefail
cd "$(dirname "$0")/.."
python3 -m pip install --quiet --upgrade pip
python3 -m pip install --quiet ".[test]"
cargo fmt --all -- --check
cargo clippy --workspace --all-targets -- -D warnings
cargo test --workspace
# The Rust robot's example: a recorded walk through the engine, one confirmed track forecasting.
replay=$(cargo run --quiet --example replay -p torso_core)
grep -q "track 1: .* s ahead" <<< "$replay"
python3 -m ruff check python tests benches
python3 -m ruff format --check python tests benches
python3 -m mypy
python3 -m pytest tests
