#!/usr/bin/env bash
# Every relative link and image of README.md and docs/*.md resolves: the file exists and, for
# `file#anchor`, the file has a heading with that GitHub anchor. Also: no page points outside
# the repository. Usage: docs_links.sh SOURCE_DIR
set -u
cd "${1:?usage: docs_links.sh SOURCE_DIR}" || exit 2
find README.md docs -name '*.md' -print0 | xargs -0 perl -CSD -Mutf8 -e '
  use strict; use warnings; use File::Basename; use File::Spec; use Cwd qw(abs_path getcwd);
  my $root = getcwd();
  my %anchors;  # file -> {anchor -> 1}
  sub anchors_of {
    my ($f) = @_;
    return $anchors{$f} if $anchors{$f};
    my %a; my %seen; my $fence = 0;
    open(my $h, "<:encoding(UTF-8)", $f) or return {};
    while (<$h>) {
      $fence = !$fence if /^\s*(```|~~~)/;
      next if $fence || !/^#{1,6}\s+(.*?)\s*#*\s*$/;
      my $s = lc $1;
      $s =~ s/`//g; $s =~ s/\[([^\]]*)\]\([^)]*\)/$1/g;  # code marks, links keep their text
      $s =~ s/[^\p{L}\p{N}\p{M} _-]//g; $s =~ s/ /-/g;
      my $n = $seen{$s}++;
      $a{$n ? "$s-$n" : $s} = 1;
    }
    return $anchors{$f} = \%a;
  }
  my $bad = 0; my $links = 0;
  for my $file (@ARGV) {
    open(my $h, "<:encoding(UTF-8)", $file) or die "cannot read $file";
    my $fence = 0;
    while (my $line = <$h>) {
      $fence = !$fence if $line =~ /^\s*(```|~~~)/;
      next if $fence;
      $line =~ s/`[^`]*`//g;  # code spans hold no links
      while ($line =~ /!?\[[^\]]*\]\(([^)\s]+)(?:\s+"[^"]*")?\)/g) {
        my $target = $1; $links++;
        next if $target =~ m{^(https?|mailto):};
        my ($path, $anchor) = split /#/, $target, 2;
        my $dest = $path eq "" ? $file : File::Spec->catfile(dirname($file), $path);
        my $full = File::Spec->canonpath(File::Spec->rel2abs($dest, $root));
        1 while $full =~ s{/[^/]+/\.\.(/|$)}{$1 ? "/" : ""}e;  # fold "dir/.." without touching the disk
        if ($target =~ m{^/} || index("$full/", "$root/") != 0) {
          print "$file:$.: points outside the repository: $target\n"; $bad++; next;
        }
        if (!-e $dest) { print "$file:$.: no such file: $target\n"; $bad++; next; }
        next unless defined $anchor && $anchor ne "";
        if ($dest !~ /\.md$/) { print "$file:$.: anchor into a non-Markdown file: $target\n"; $bad++; next; }
        if (!anchors_of($dest)->{$anchor}) { print "$file:$.: no heading #$anchor in $dest\n"; $bad++; }
      }
    }
    close $h;
  }
  print "$links links checked, $bad broken\n";
  exit($bad ? 1 : 0);
'
status=$?
# Nothing in the repository names a file outside it.
paths=()
for p in README.md docs sim app render tests tools setup.sh .ci CMakeLists.txt; do [ -e "$p" ] && paths+=("$p"); done
if grep -rnE "\.\./shared|DESIGN\.md" "${paths[@]}" --exclude=docs_links.sh --exclude=docs_tools_tests.sh; then
  echo "FAILED: the lines above point outside the repository"
  status=1
fi
exit $status
