# Shared by the package tests: fail with a reason, skip when a tool is absent.
fail() { echo "FAIL: $*"; exit 1; }
skip() { echo "SKIP: $*"; exit 77; }
