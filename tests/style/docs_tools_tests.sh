#!/usr/bin/env bash
# The docs checks can fail: docs_links.sh on a page with a missing file, a missing heading and a
# link outside the repository; gen-docs.sh --check on a stale generated section, which
# gen-docs.sh then rewrites. Usage: APICLAB=... docs_tools_tests.sh SOURCE_DIR
set -u
src="${1:?usage: docs_tools_tests.sh SOURCE_DIR}"
: "${APICLAB:?set APICLAB to the apiclab executable}"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
passed=0 failed=0
ok() { passed=$((passed + 1)); echo "ok: $1"; }
nok() { failed=$((failed + 1)); echo "FAILED: $1"; }

# docs_links.sh: a good page passes, each kind of broken link is named.
mkdir -p "$tmp/links/docs"
printf '# Top\n\n## A heading, with `code`\n\n[ok](docs/b.md#second-part) [self](#a-heading-with-code)\n' \
  >"$tmp/links/README.md"
printf '# B\n\n## Second part\n\n[back](../README.md#top)\n' >"$tmp/links/docs/b.md"
if bash "$src/tests/style/docs_links.sh" "$tmp/links" >"$tmp/out" 2>&1; then ok "good links pass"
else nok "good links pass: $(cat "$tmp/out")"; fi
printf '[gone](docs/none.md) [anchor](docs/b.md#third-part) [out](../shared/x.md)\n' >>"$tmp/links/README.md"
bash "$src/tests/style/docs_links.sh" "$tmp/links" >"$tmp/out" 2>&1
status=$?
if [ $status != 0 ] && grep -q 'no such file: docs/none.md' "$tmp/out" &&
  grep -q 'no heading #third-part' "$tmp/out" && grep -q 'outside the repository: ../shared/x.md' "$tmp/out"; then
  ok "broken links are named"
else nok "broken links (status $status): $(cat "$tmp/out")"; fi

# gen-docs.sh: a stale section fails --check, a rewrite makes it current, the rest is kept.
mkdir -p "$tmp/gen/tools" "$tmp/gen/docs"
cp "$src/tools/gen-docs.sh" "$tmp/gen/tools/"
{
  echo "# Scene keys"
  echo "<!-- BEGIN GENERATED scene-keys: tools/gen-docs.sh scene-keys -->"
  echo "| stale |"
  echo "<!-- END GENERATED scene-keys -->"
  echo "kept after"
} >"$tmp/gen/docs/scene-keys.md"
if ! "$tmp/gen/tools/gen-docs.sh" --check scene-keys >"$tmp/out" 2>&1 && grep -q "is stale" "$tmp/out"; then
  ok "a stale section fails --check"
else nok "stale section: $(cat "$tmp/out")"; fi
"$tmp/gen/tools/gen-docs.sh" scene-keys >/dev/null 2>&1
if "$tmp/gen/tools/gen-docs.sh" --check scene-keys >"$tmp/out" 2>&1 &&
  grep -q '^| `domain.dx` |' "$tmp/gen/docs/scene-keys.md" && ! grep -q stale "$tmp/gen/docs/scene-keys.md" &&
  [ "$(head -1 "$tmp/gen/docs/scene-keys.md")" = "# Scene keys" ] && [ "$(tail -1 "$tmp/gen/docs/scene-keys.md")" = "kept after" ]; then
  ok "gen-docs rewrites the section and keeps the page around it"
else nok "rewrite: $(cat "$tmp/out")"; fi
if ! "$tmp/gen/tools/gen-docs.sh" nonsense >"$tmp/out" 2>&1 && grep -q "unknown generator" "$tmp/out"; then
  ok "an unknown generator is refused"
else nok "unknown generator: $(cat "$tmp/out")"; fi

# Every registry key is on the generated page (the page comes from the registry, not by hand).
"$APICLAB" docs scene-keys >"$tmp/keys.md"
missing=0
for key in $("$APICLAB" run --help | grep -oE '^ +[a-z_]+\.[a-z_.*0-9+-]+' | tr -d ' ' | sort -u); do
  grep -q "^| \`$key\` |" "$tmp/keys.md" || { echo "not on the page: $key"; missing=1; }
done
[ $missing = 0 ] && ok "every key of run --help is on the scene-keys page" || nok "keys missing from the page"

echo "$passed passed, $failed failed"
[ $failed = 0 ]
