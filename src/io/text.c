/* Numbers as text for the text formats: see text.h. */
#define _POSIX_C_SOURCE 200809L /* newlocale, uselocale */

#include "text.h"

#include <errno.h>
#include <locale.h>
#include <stdlib.h>

int vn_io_c_locale_enter(vn_io_c_locale* l)
{
	locale_t c = newlocale(LC_NUMERIC_MASK, "C", (locale_t)0);
	if (!c)
		return 0;
	l->c = c;
	l->previous = uselocale(c);
	return 1;
}

void vn_io_c_locale_leave(vn_io_c_locale* l)
{
	uselocale((locale_t)l->previous);
	freelocale((locale_t)l->c);
}

void vn_io_put(vn_io_text_out* w, const char* text)
{
	if (!w->failed && fputs(text, w->out) == EOF) {
		w->failed = 1;
		w->error_number = errno;
	}
}

void vn_io_put_float9(vn_io_text_out* w, double v)
{
	char text[40];
	snprintf(text, sizeof text, " %.9g", v);
	vn_io_put(w, text);
}

void vn_io_put_float(vn_io_text_out* w, float v)
{
	char text[40];
	for (int digits = 6;; digits++) {
		snprintf(text, sizeof text, " %.*g", digits, (double)v);
		if (digits == 9 || (float)strtod(text, NULL) == v)
			break;
	}
	vn_io_put(w, text);
}

void vn_io_put_exact(vn_io_text_out* w, const char* separator, double v)
{
	char text[40];
	for (int digits = 15;; digits++) {
		snprintf(text, sizeof text, "%s%.*g", separator, digits, v);
		if (digits == 17 || strtod(text, NULL) == v)
			break;
	}
	vn_io_put(w, text);
}
