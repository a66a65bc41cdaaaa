/* Options whose value is two whole numbers joined by 'x' (--grid 48x64,
 * --views 192x108): digits, 'x', digits and nothing else (sscanf's "%dx%d"
 * had taken "8x16x3", "8x16abc" and "+8x+16"). */
#ifndef SKYFIT_CLI_SIZE_PAIR_OPTION_H
#define SKYFIT_CLI_SIZE_PAIR_OPTION_H

/* Parses text into *a and *b, each in lo..hi. Returns 0, or -1 (outputs
 * untouched) when text is anything else. */
int sf_cli_parse_size_pair(const char *text, int lo, int hi, int *a, int *b);

#endif
