/* Text written into HTML or SVG (report.html, the plots' SVG files): the
 * characters markup reserves, escaped. */
#ifndef SKYFIT_CODEGEN_HTML_ESCAPE_H
#define SKYFIT_CODEGEN_HTML_ESCAPE_H

#include <stdio.h>

static inline void sf_html_escape(FILE *f, const char *s) {
  for (; *s; ++s) {
    switch (*s) {
      case '<': fputs("&lt;", f); break;
      case '>': fputs("&gt;", f); break;
      case '&': fputs("&amp;", f); break;
      case '"': fputs("&quot;", f); break;
      case '\'': fputs("&#39;", f); break;
      default: fputc(*s, f);
    }
  }
}

#endif
