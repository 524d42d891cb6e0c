#!/bin/sh
# radkit.1, the manual page, written from the program's own help texts:
#
#   sh scripts/manpage.sh build/radkit > radkit.1
#
# Every command's options are documented once, in its --help string
# (core/cli/cmd_*.c, and core/cli/scene_options.c for the options every
# scene-reading command shares); this script only lays them out in troff, so
# the page and --help cannot disagree.  The commands are those 'radkit --help'
# lists under "commands:".
#
# The layout of a help text, as the script reads it:
#   usage: ...            the synopsis, up to the first blank line
#   "  --opt ARG  text"   an option (two spaces, a dash); its description goes
#                         on in lines indented further.  ARG is one word after
#                         a single space (N, RULE, WxH) or a quoted "r g b";
#                         an option line ending in ',' continues on the next
#   prose at column 0     a paragraph, filled
#   other indented lines  kept as they are (lists, tables)
#   example: ...          kept as it is
# Option descriptions keep their line breaks (they hold small tables).  An
# option written identically in several commands (the scene options) is
# printed once, under SCENE OPTIONS, and each command names it there.
set -eu
radkit=${1:?usage: sh scripts/manpage.sh RADKIT_BINARY}
version=$("$radkit" --version)
commands=$("$radkit" --help | awk '/^commands:/ { on = 1; next } on && /^$/ { exit } on && /^  [a-z]/ { print $1 }')
[ -n "$commands" ] || { echo "manpage: no commands in '$radkit --help'" >&2; exit 1; }

{
    echo "@@section"
    "$radkit" --help
    for c in $commands; do
        echo "@@section $c"
        "$radkit" "$c" --help
    done
} | awk -v version="$version" '
function esc(s) {
    gsub(/\\/, "\\e", s)
    gsub(/-/, "\\-", s)
    if (s ~ /^[.\047]/) s = "\\&" s
    return s
}
function indent(s) { match(s, /^ */); return RLENGTH }
# Split an option line (leading spaces removed) into its term and the
# column where its description starts: sets TERM, DESC.
function split_option(s,    t, m) {
    t = ""
    while (1) {
        if (!match(s, /^-[-A-Za-z0-9]+/)) break
        t = t substr(s, 1, RLENGTH); s = substr(s, RLENGTH + 1)
        if (match(s, /^ "[^"]*"/) || (match(s, /^ [A-Z][A-Za-z0-9]*/) && substr(s, RLENGTH + 1, 1) ~ /^([ ,]|)$/)) {
            t = t substr(s, 1, RLENGTH); s = substr(s, RLENGTH + 1)
        }
        if (s ~ /^, *-/ || s ~ /^,$/) { sub(/^, */, "", s); t = t ", "; continue }
        break
    }
    DESC = s; sub(/^ +/, "", DESC)
    TERM = t
}
function term_troff(t,    n, parts, i, p, out, sp, m) {
    n = split(t, parts, /, /)
    out = ""
    for (i = 1; i <= n; i++) {
        p = parts[i]
        if (p == "") continue
        sp = index(p, " ")
        if (sp) { m = esc(substr(p, sp + 1)); gsub(/ /, "\\ ", m); p = "\\fB" esc(substr(p, 1, sp - 1)) "\\fR\\ \\fI" m "\\fR" }
        else p = "\\fB" esc(p) "\\fR"
        out = out (out == "" ? "" : ", ") p
    }
    return out
}
# Items of every section: kind (usage, prose, pre, option), text.
function add(kind, text) { n = ++count[sec]; kind_[sec, n] = kind; text_[sec, n] = text; cur = kind }
function append(text) { text_[sec, count[sec]] = text_[sec, count[sec]] "\n" text }
BEGIN { sec = -1 }
/^@@section/ { sec++; name[sec] = $2; count[sec] = 0; cur = ""; pending = ""; next }
/^$/ { cur = ""; next }
# Usage lines go on aligned under the command; the synopsis drops "usage: ".
cur == "usage" { line = $0; sub(/^       /, "", line); append(line); next }
/^usage:/ { add("usage", $0); next }
/^  -/ {
    line = substr($0, 3)
    if (pending != "") line = pending " " line
    split_option(line)
    if (TERM ~ /, *$/ && DESC == "") { pending = TERM; sub(/ +$/, "", pending); next }
    pending = ""
    add("option", TERM)
    col[sec, count[sec]] = length($0) - length(DESC)
    desc[sec, count[sec]] = DESC
    next
}
cur == "option" && indent($0) > 2 {
    c = col[sec, count[sec]]; k = indent($0)
    desc[sec, count[sec]] = desc[sec, count[sec]] "\n" substr($0, (k < c ? k : c) + 1)
    next
}
/^example:/ { add("pre", $0); next }
/^[^ ]/ { if (cur == "prose") append($0); else add("prose", $0); next }
{ if (cur == "pre") append($0); else add("pre", $0) }
function lines(s, indented,    n, l, i, out) {
    n = split(s, l, "\n"); out = ""
    for (i = 1; i <= n; i++) out = out esc(l[i]) "\n"
    return out
}
function emit(s, i,    k, t) {
    k = kind_[s, i]; t = text_[s, i]
    if (k == "usage") { sub(/^usage: /, "", t); printf ".PP\n.nf\n%s.fi\n", lines(t) }
    else if (k == "prose") printf ".PP\n%s", lines(t)
    else if (k == "pre") printf ".PP\n.RS 2\n.nf\n%s.fi\n.RE\n", lines(t)
    else if (k == "option") printf ".TP\n%s\n.nf\n%s.fi\n", term_troff(t), lines(desc[s, i])
}
END {
    # An option written identically in more than one command is shared.
    for (s = 1; s <= sec; s++)
        for (i = 1; i <= count[s]; i++)
            if (kind_[s, i] == "option") {
                key = text_[s, i] SUBSEP desc[s, i]
                if (!(key in seen_in) || seen_in[key] != s) { uses[key]++; seen_in[key] = s }
                if (!(key in first)) { first[key] = s SUBSEP i; order[++nshared] = key }
            }
    # The name line: "radkit is a research toolkit ..." of the top help.
    summary = "radkit"
    for (i = 1; i <= count[0]; i++)
        if (kind_[0, i] == "prose" && text_[0, i] ~ /^radkit is /) {
            summary = text_[0, i]; sub(/^radkit is /, "", summary); sub(/\.$/, "", summary); break
        }
    v = version; sub(/^radkit /, "", v)
    printf ".\\\" Generated by scripts/manpage.sh from the --help texts of %s; do not edit.\n", version
    printf ".TH RADKIT 1 \"\" \"radkit %s\" \"radkit manual\"\n", v
    print ".nh"
    print ".ad l"
    print ".SH NAME"
    printf "radkit \\- %s\n", esc(summary)
    print ".SH SYNOPSIS"
    for (s = 0; s <= sec; s++)
        for (i = 1; i <= count[s]; i++)
            if (kind_[s, i] == "usage") { t = text_[s, i]; sub(/^usage: /, "", t); printf ".nf\n%s.fi\n", lines(t) }
    print ".SH DESCRIPTION"
    for (i = 1; i <= count[0]; i++) if (kind_[0, i] != "usage") emit(0, i)
    print ".SH COMMANDS"
    for (s = 1; s <= sec; s++) {
        printf ".SS %s\n", name[s]
        shared_names = ""
        for (i = 1; i <= count[s]; i++) {
            if (kind_[s, i] == "usage") continue
            key = text_[s, i] SUBSEP desc[s, i]
            if (kind_[s, i] == "option" && uses[key] > 1) {
                shared_names = shared_names (shared_names == "" ? "" : ", ") term_troff(text_[s, i])
                # The shared options stand together; name them where they stood.
                if (i == count[s] || kind_[s, i + 1] != "option" || uses[text_[s, i + 1] SUBSEP desc[s, i + 1]] <= 1) {
                    printf ".TP\n\\fIscene options\\fR\n%s: see \\fBSCENE OPTIONS\\fR.\n", shared_names
                    shared_names = ""
                }
                continue
            }
            emit(s, i)
        }
    }
    printed = 0
    for (j = 1; j <= nshared; j++) {
        key = order[j]
        if (uses[key] <= 1) continue
        if (!printed) {
            print ".SH SCENE OPTIONS"
            # The commands that take them, in the order of the top help.
            nt = 0
            for (s = 1; s <= sec; s++)
                for (i = 1; i <= count[s]; i++)
                    if (kind_[s, i] == "option" && uses[text_[s, i] SUBSEP desc[s, i]] > 1) { taker[++nt] = name[s]; break }
            t = ""
            for (k = 1; k <= nt; k++) t = t (k == 1 ? "" : (k == nt ? " and " : ", ")) "\\fB" taker[k] "\\fR"
            printf "The options that %s share.\n", t
            printed = 1
        }
        split(first[key], at, SUBSEP)
        emit(at[1], at[2])
    }
}
'
