#!/usr/bin/env bash
# The installed man pages are the installed programs' --help: every option a --help prints (each
# of dynweigh's subcommands too) is in the man page, its version is the program's, and groff
# renders it without a warning.
set -euo pipefail
. "$(dirname "$0")/common.sh"
root=$1
bin=$root/usr/bin
man=$root/usr/share/man/man1
unset DYNWEIGH_SCENES

options() { grep -oE -- '(^|[^a-z0-9-])--[a-z][a-z0-9-]*' | grep -oE -- '--[a-z][a-z0-9-]*' | sort -u; }
page_text() { zcat "$man/$1.1.gz" | sed 's/\\-/-/g'; }

check_page() {
  local program=$1 help=$2
  [ -f "$man/$program.1.gz" ] || fail "no man page $program.1.gz"
  local text missing=""
  text=$(page_text "$program")
  for option in $(options <<< "$help"); do
    grep -qF -- "$option" <<< "$text" || missing="$missing $option"
  done
  [ -z "$missing" ] || fail "$program.1 lacks$missing (in its --help)"
  local version
  version=$("$bin/$program" --version | awk '{print $2}')
  grep -q "^\.TH .*\"$program $version\"" <<< "$text" || fail "$program.1 is not of version $version"
  local warnings
  warnings=$(zcat "$man/$program.1.gz" | groff -man -Tutf8 -ww -z 2>&1) || true
  [ -z "$warnings" ] || fail "groff warns on $program.1: $warnings"
  echo "$program.1: $(options <<< "$help" | wc -l) options, version $version"
}

check_page dynweigh-fw "$("$bin/dynweigh-fw" --help)"
help=$("$bin/dynweigh" --help)
for sub in $(awk '/^  [a-z]/ {print $1}' <<< "$help"); do
  help+=$'\n'$("$bin/dynweigh" "$sub" --help 2>&1)
  zcat "$man/dynweigh.1.gz" | grep -q "^\.SS \"dynweigh $sub\"" || fail "dynweigh.1 has no section for $sub"
done
check_page dynweigh "$help"
echo PASS
