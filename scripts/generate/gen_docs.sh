#!/usr/bin/env bash
# Regenerates docs/scenarios.md from the scenario schema compiled into viaduct.
# Usage: scripts/generate/gen_docs.sh [path/to/viaduct]   (default: build/release/viaduct)
set -euo pipefail
cd "$(dirname "$0")/../.."
bin=${1:-build/release/viaduct}
{
  cat docs/scenarios.head.md
  "$bin" schema
} > docs/scenarios.md
echo "wrote docs/scenarios.md"
