#!/usr/bin/perl
# list_commands.pl FILE...: prints "command<TAB>file" for every word in command position of the
# given shell scripts (and of Snakemake files' shell: blocks, and of C++ std::system() strings), so
# that deps_test.sh can map each external command to the Debian package that provides it.
#
# A static approximation of the shell grammar that errs towards finding too much: here-documents,
# comments and single-quoted strings (jq, awk and sed programs) are dropped; a double-quoted
# string keeps only its command substitutions; $(...) and `...` are scanned recursively with fresh
# quoting, as the shell does; what remains is split at | || && ; ( ) { } and the keywords that
# start a command list. The first word of each piece that is not an assignment or a redirection is
# a command; so is the word after a wrapper (nice -n N, timeout N, env, xargs, exec, time), after
# `--` (tests/cli/lib.sh's `expect_true "what" -- command ...`) and in `bash -c "..."`.
use strict;
use warnings;

my %keywords = map { $_ => 1 } qw(if then else elif fi for while until do done case esac in
    function select return local export declare readonly set shift unset trap wait break continue
    eval source . true false exit read printf echo test cd pwd type mapfile readarray let shopt
    command builtin jobs kill);
my %wrappers = map { $_ => 1 } qw(nice timeout env xargs exec time nohup setsid stdbuf ionice
    flock);

# substitution(TEXT, POS, BARE_ARITHMETIC): at POS, an arithmetic expansion $((...)) (or, when
# BARE_ARITHMETIC, a (( )) command) gives (' X ', the position after it); a command substitution
# $(...) or `...` gives (its command text, the position after it); anything else gives ().
sub substitution {
    my ($t, $i, $bare) = @_;
    if (substr($t, $i, 3) eq '$((' || ($bare && substr($t, $i, 2) eq '((')) {
        my $j = index($t, '))', $i);
        return (' X ', $j < 0 ? length($t) : $j + 2);
    }
    my $c = substr($t, $i, 1);
    return () unless substr($t, $i, 2) eq '$(' || $c eq '`';
    return scan($t, $i + ($c eq '`' ? 1 : 2), $c eq '`' ? '`' : ')');
}

# scan(TEXT, POS, END): the shell text from POS up to an unquoted END ('' = the end) as command
# text, and the position after END.
sub scan {
    my ($t, $i, $end) = @_;
    my ($out, $n) = ('', length($t));
    while ($i < $n) {
        my $c = substr($t, $i, 1);
        return ($out, $i + 1) if $end ne '' && $c eq $end;
        if ($c eq '\\') { $out .= ' '; $i += 2; next; }
        if ($c eq "'") {
            my $j = index($t, "'", $i + 1);
            $i = $j < 0 ? $n : $j + 1;
            $out .= ' X ';
            next;
        }
        if ($c eq '"') {
            my ($inner, $j) = scan_double($t, $i + 1);
            $out .= " X $inner ";
            $i = $j;
            next;
        }
        if ($c eq '#' && ($i == 0 || substr($t, $i - 1, 1) =~ /[\s;(|&]/)) {
            my $j = index($t, "\n", $i);
            $i = $j < 0 ? $n : $j;
            next;
        }
        if (my ($inner, $j) = substitution($t, $i, 1)) {
            $out .= " X ; $inner ; ";
            $i = $j;
            next;
        }
        if (substr($t, $i, 2) eq '${') {
            my ($depth, $j) = (0, $i + 1);
            for (; $j < $n; $j++) {
                my $d = substr($t, $j, 1);
                $depth++ if $d eq '{';
                $depth-- if $d eq '}';
                last if $depth == 0;
            }
            $out .= 'X';
            $i = $j + 1;
            next;
        }
        $out .= $c;
        $i++;
    }
    return ($out, $i);
}

# scan_double(TEXT, POS): the command substitutions of the double-quoted string whose text starts
# at POS, and the position after its closing quote.
sub scan_double {
    my ($t, $i) = @_;
    my ($out, $n) = ('', length($t));
    while ($i < $n) {
        my $c = substr($t, $i, 1);
        return ($out, $i + 1) if $c eq '"';
        if ($c eq '\\') { $i += 2; next; }
        if (my ($inner, $j) = substitution($t, $i, 0)) {
            $out .= " ; $inner ; ";
            $i = $j;
            next;
        }
        $i++;
    }
    return ($out, $i);
}

# The text of a double-quoted string as the shell passes it on (\" \$ \\ \` unescaped).
sub unescape {
    my ($s) = @_;
    $s =~ s/\\(["\$\\`])/$1/g;
    return $s;
}

for my $file (@ARGV) {
    open(my $fh, '<', $file) or die "list_commands.pl: $file: $!\n";
    my $text = do { local $/; <$fh> };
    close($fh);
    if ($file =~ /\.(cpp|h)$/) {
        # C++: the first word of each std::system("...") command string.
        while ($text =~ /std::system\(\s*\(?\s*"\s*([A-Za-z][A-Za-z0-9._+-]*)/g) { print "$1\t$file\n"; }
        next;
    }
    if ($file =~ /\.smk$/) {
        # Snakemake: only the shell: blocks are shell; each body is Python string literals.
        my $shell = '';
        while ($text =~ /^\s*shell:\s*\n((?:[ \t]+(?:"""(?:.|\n)*?"""|"[^"\n]*"|'[^'\n]*')\s*\n)+)/mg) {
            my $body = $1;
            $body =~ s/^\s*(?:"""|"|')//mg;
            $body =~ s/(?:"""|"|')\s*$//mg;
            $body =~ s/\{\{/{/g;
            $body =~ s/\}\}/}/g;
            $body =~ s/\{[A-Za-z_.\[\]0-9]*\}/X/g;  # Snakemake's {input}, {params.x}, {wildcards.id}
            $shell .= "$body\n";
        }
        $text = $shell;
    }
    $text =~ s/\\\n/ /g;                                          # line continuations
    $text =~ s/<<-?\s*['"]?(\w+)['"]?[^\n]*\n.*?\n\s*\1\n/\n/gs;           # here-documents
    $text =~ s/\b(?:bash|sh) -c\s+(?:"((?:[^"\\]|\\.)*)"|'([^']*)')/" ; " . unescape($1 \/\/ $2) . " ; "/ge;
    ($text) = scan($text, 0, '');
    $text =~ s/\b[A-Za-z_][A-Za-z0-9_]*\+?=\([^()]*\)/X/g;   # array assignments
    $text =~ s/\[\[.*?\]\]/X/g;                                  # [[ tests ]] (regexes)
    $text =~ s/(^|\n)\s*[\w*|.-]+\)/$1/g;                  # case patterns: `name)`
    for my $piece (split /\|\||&&|[|;&(){}\n!]|\bthen\b|\bdo\b|\belse\b/, $text) {
        my @words = split ' ', $piece;
        print STDERR "PIECE: $piece\n" if $ENV{LIST_COMMANDS_DEBUG};
        while (@words) {
            my $w = shift @words;
            next if $w =~ /^[A-Za-z_][A-Za-z0-9_]*(\[[^\]]*\])?\+?=/;     # assignment
            next if $w =~ /^[0-9]*[<>]/;                                  # redirection
            $w = shift @words if $w eq '--' && @words;
            my $path = $w =~ m{^/(?:usr/)?s?bin/([A-Za-z0-9._+-]+)$} ? $1 : '';
            $w = $path if $path ne '';
            if ($wrappers{$w}) {
                # exec and a bare time are shell words; /usr/bin/time is the time package.
                print "$w\t$file\n" unless ($w eq 'exec' || $w eq 'time') && $path eq '';
                # The wrapper's own options and numeric arguments (nice -n 10, timeout 5s).
                shift @words while @words && ($words[0] =~ /^-/ || $words[0] =~ /^[0-9.]+[smh]?$/
                                              || $words[0] =~ /^[A-Za-z_][A-Za-z0-9_]*=/);
                next;
            }
            last if $keywords{$w};
            print "$w\t$file\n" if $w =~ /^[a-z][a-z0-9._+-]*$/;
            last;
        }
    }
}
