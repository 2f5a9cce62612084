#!/bin/sh
# A program's man page from its --help and --version, with help2man; for `dynweigh`, a section
# SUBCOMMANDS holds each subcommand's own --help. Writes OUT (gzip -9n).
# usage: man_page.sh PROGRAM "ONE-LINE DESCRIPTION" OUT.1.gz
set -eu
program=$1
description=$2
out=$3
scratch=$(mktemp -d)
trap 'rm -rf "$scratch"' EXIT

# Literal text in roff: backslashes escaped, hyphens as minus signs (so options copy and paste),
# a line starting with . or ' not taken for a request.
roff_literal() { sed -e 's/\\/\\e/g' -e 's/-/\\-/g' -e "s/^\\([.']\\)/\\\\\\&\\1/"; }

: > "$scratch/include"
if [ "$(basename "$program")" = dynweigh ]; then
  subcommands=$("$program" --help | awk '/^  [a-z]/ {print $1}')
  {
    echo "[SUBCOMMANDS]"
    echo "Each subcommand takes its own options; \\fBdynweigh\\fR \\fIsubcommand\\fR \\fB\\-\\-help\\fR prints them:"
    for sub in $subcommands; do
      echo ".SS \"dynweigh $sub\""
      echo ".nf"
      "$program" "$sub" --help 2>&1 | roff_literal
      echo ".fi"
    done
  } > "$scratch/include"
fi
cat >> "$scratch/include" <<'SEE_ALSO'
[SEE ALSO]
The README in /usr/share/doc/dynweigh and the pages in /usr/share/doc/dynweigh/docs: the console's
commands (console.md), errors and faults (troubleshooting.md), the scenes (scenes.md), the CAN link
(can-protocol.md), and installing the service \fBdynweigh\-fw@.service\fR (targets.md).
SEE_ALSO

help2man --no-info --no-discard-stderr --name="$description" --include="$scratch/include" \
  --output="$scratch/page.1" "$program"
gzip -9n < "$scratch/page.1" > "$out"
