#!/usr/bin/env bash
# The format and lint checks, each reporting which files it rejects (exit 1 if any does):
#   clang-format  src/ and tests/cpp against .clang-format (fix: clang-format -i FILE)
#   ruff          the Python code, configured in pyproject.toml (fix: ruff check --fix, or by hand)
#   snakefmt      the workflow's Snakefile and rules (fix: snakefmt workflow/)
#   ShellCheck    every shell script of the project: the tracked *.sh files and .ci/run (the
#                 Debian package, installed by tools/install-deps.sh test; fix by hand, or with a
#                 disable=SCnnnn directive and the reason where the construct is meant)
# ruff and snakefmt come from the project environment .venv/ (pinned and hashed in
# requirements/project.txt; tools/install-deps.sh makes it when missing or out of date).
#   tools/lint.sh
set -uo pipefail
cd "$(dirname "$0")/.." || exit 1
failed=()

# 1. C++ format.
mapfile -t cxx < <(find src tests/cpp -name '*.cpp' -o -name '*.hpp' | sort)
bad=$(clang-format --dry-run --Werror "${cxx[@]}" 2>&1 | sed -nE 's/^([^:]+):[0-9]+:[0-9]+: error:.*/\1/p' | sort -u)
if [ -n "$bad" ] || ! clang-format --dry-run --Werror "${cxx[@]}" >/dev/null 2>&1; then
  echo "lint: clang-format: these files are not formatted (fix: clang-format -i FILE):"
  # shellcheck disable=SC2001  # indents every line, which ${var//} cannot
  sed 's/^/  /' <<<"${bad:-(clang-format itself failed; run it by hand)}"
  failed+=(clang-format)
else
  echo "lint: clang-format: ${#cxx[@]} C++ files formatted"
fi

# 2. The pinned Python linters: the project environment's (.venv/, made by
# tools/install-deps.sh from requirements/project.txt when missing or out of date).
venv=.venv
if ! tools/install-deps.sh venv; then
  echo "lint: FAILED to make $venv/ (python3-venv missing? offline?)"
  exit 1
fi

# 3. Python lint (rules and paths from pyproject.toml).
if out=$("$venv/bin/ruff" check --no-cache --output-format concise 2>&1); then
  echo "lint: ruff: clean"
else
  echo "lint: ruff: these files have problems (fix: $venv/bin/ruff check --fix, or by hand):"
  # shellcheck disable=SC2001  # indents every line
  sed 's/^/  /' <<<"$out"
  failed+=(ruff)
fi

# 4. Snakemake format (snakefmt formats shell: blocks with the venv's shfmt, so the venv's
# bin/ comes first on PATH).
if out=$(PATH="$PWD/$venv/bin:$PATH" "$venv/bin/snakefmt" --check --verbose workflow/ 2>&1); then
  echo "lint: snakefmt: workflow/ formatted"
else
  echo "lint: snakefmt: these files are not formatted (fix: PATH=$venv/bin:\$PATH snakefmt workflow/):"
  grep -E '^\[(ERROR|WARNING)\]|different from original' <<<"$out" |
    sed -E 's/^\[DEBUG\] In file "([^"]+)":.*/\1/; s/^/  /'
  failed+=(snakefmt)
fi

# 5. Shell scripts: every *.sh file and every file whose first line is a shell's #! that git
# tracks or would (untracked but not ignored), at every severity; sourced files are followed
# (-x) from their `# shellcheck source=PATH` lines, PATH from the repository's root.
shebang='^#!/(usr/)?bin/(env )?(ba)?sh\b'
mapfile -t sh < <({
  git ls-files --cached --others --exclude-standard '*.sh'
  git grep --untracked -lE "$shebang" -- ':!*.sh' | while read -r f; do
    head -n 1 "$f" | grep -qE "$shebang" && echo "$f"
  done
} | sort -u)
if ! command -v shellcheck >/dev/null; then
  echo "lint: shellcheck: not installed (tools/install-deps.sh test installs it)"
  failed+=(shellcheck)
elif [ ${#sh[@]} -eq 0 ]; then
  echo "lint: shellcheck: no shell scripts found (not a git checkout?)"
  failed+=(shellcheck)
elif out=$(shellcheck -x -f gcc "${sh[@]}" 2>&1); then
  echo "lint: shellcheck: ${#sh[@]} shell scripts clean"
else
  echo "lint: shellcheck: these scripts have problems (fix by hand, or a disable=SCnnnn directive with the reason):"
  # shellcheck disable=SC2001  # indents every line
  sed 's/^/  /' <<<"$out"
  failed+=(shellcheck)
fi

if [ ${#failed[@]} -gt 0 ]; then
  echo "lint: FAILED: ${failed[*]}"
  exit 1
fi
echo "lint: all checks passed"
