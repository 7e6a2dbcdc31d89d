/* Minimal SVG charts for vneval: line charts with a log or linear x axis and
 * bar charts, with readable axes, a legend and the Okabe-Ito colour-blind-safe
 * palette (Okabe & Ito 2008). Header-only: vneval is its only user. */
#ifndef VN_TOOLS_SVGPLOT_H
#define VN_TOOLS_SVGPLOT_H

#include <math.h>
#include <stdio.h>

/* Okabe-Ito, skipping yellow (too light on white); the series also differ
 * by dash pattern so that they stay apart in grey-scale print. Past the
 * palette's seven (the paper's schemes) the colours repeat with new dashes. */
static const char* const svg_colours[] = {"#000000", "#E69F00", "#56B4E9", "#009E73", "#0072B2", "#D55E00",
                                          "#CC79A7", "#D55E00", "#0072B2", "#009E73", "#CC79A7", "#000000"};
static const char* const svg_dashes[] = {"",    "8,3",       "2,2", "",   "6,2,2,2",         "4,4",
                                         "",    "1,3", "12,3,2,3", "10,4", "3,2,3,2,8,2", "1,2"};
#define SVG_SERIES_MAX 12

typedef struct svg_panel {
	double x, y, w, h;            /* plot area in SVG units */
	double x0, x1, y0, y1;        /* data range */
	int xlog;                     /* log10 x axis */
	int categories;               /* bar chart: no x grid or x tick labels */
	int ylog;                     /* log10 y axis */
} svg_panel;

static inline double svg_px(const svg_panel* p, double v)
{
	double t = p->xlog ? (log10(v) - log10(p->x0)) / (log10(p->x1) - log10(p->x0)) : (v - p->x0) / (p->x1 - p->x0);
	t = t < 0 ? 0 : t > 1 ? 1 : t;
	return p->x + t * p->w;
}

static inline double svg_py(const svg_panel* p, double v)
{
	double t = p->ylog ? (log10(v) - log10(p->y0)) / (log10(p->y1) - log10(p->y0)) : (v - p->y0) / (p->y1 - p->y0);
	t = t < 0 ? 0 : t > 1 ? 1 : t;
	return p->y + p->h - t * p->h;
}

/* The smallest 4 * step >= v with step 1, 2 or 5 times a power of ten, so
 * that the four y grid lines fall on round numbers. */
static inline double svg_nice_max(double v)
{
	const double base = pow(10, floor(log10(v / 4)));
	const double steps[] = {1, 2, 5, 10};
	for (int i = 0; i < 4; ++i)
		if (4 * steps[i] * base >= v)
			return 4 * steps[i] * base;
	return 40 * base;
}

/* The label of decade 10^d: plain for 1e-3 .. 1e3, else 1eD. */
static inline void svg_decade_label(char* label, size_t size, double d)
{
	if (d >= 0 && d <= 3)
		snprintf(label, size, "%.0f", pow(10, d));
	else if (d >= -3 && d < 0)
		snprintf(label, size, "%.*f", (int)-d, pow(10, d));
	else
		snprintf(label, size, "1e%.0f", d);
}

static inline void svg_begin(FILE* f, double w, double h, const char* title)
{
	fprintf(f,
	        "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"%.0f\" height=\"%.0f\" viewBox=\"0 0 %.0f %.0f\" "
	        "font-family=\"Helvetica, Arial, sans-serif\" font-size=\"13\">\n"
	        "<rect width=\"100%%\" height=\"100%%\" fill=\"white\"/>\n"
	        "<text x=\"%.1f\" y=\"22\" text-anchor=\"middle\" font-size=\"15\" font-weight=\"bold\">%s</text>\n",
	        w, h, w, h, w / 2, title);
}

static inline void svg_end(FILE* f)
{
	fprintf(f, "</svg>\n");
}

/* Frame, grid, ticks and labels of a panel. Log axes tick every decade. */
static inline void svg_axes(FILE* f, const svg_panel* p, const char* xlabel, const char* ylabel, const char* title)
{
	fprintf(f, "<g stroke=\"#dddddd\" stroke-width=\"1\">\n");
	if (p->xlog && !p->categories) {
		for (double d = ceil(log10(p->x0) - 1e-9); d <= log10(p->x1) + 1e-9; d += 1)
			fprintf(f, "<line x1=\"%.1f\" y1=\"%.1f\" x2=\"%.1f\" y2=\"%.1f\"/>\n", svg_px(p, pow(10, d)), p->y,
			        svg_px(p, pow(10, d)), p->y + p->h);
	} else if (!p->categories) {
		for (int i = 0; i <= 4; ++i) {
			const double v = p->x0 + (p->x1 - p->x0) * i / 4;
			fprintf(f, "<line x1=\"%.1f\" y1=\"%.1f\" x2=\"%.1f\" y2=\"%.1f\"/>\n", svg_px(p, v), p->y, svg_px(p, v),
			        p->y + p->h);
		}
	}
	if (p->ylog) {
		for (double d = ceil(log10(p->y0) - 1e-9); d <= log10(p->y1) + 1e-9; d += 1)
			fprintf(f, "<line x1=\"%.1f\" y1=\"%.1f\" x2=\"%.1f\" y2=\"%.1f\"/>\n", p->x, svg_py(p, pow(10, d)),
			        p->x + p->w, svg_py(p, pow(10, d)));
	} else {
		for (int i = 0; i <= 4; ++i) {
			const double v = p->y0 + (p->y1 - p->y0) * i / 4;
			fprintf(f, "<line x1=\"%.1f\" y1=\"%.1f\" x2=\"%.1f\" y2=\"%.1f\"/>\n", p->x, svg_py(p, v),
			        p->x + p->w, svg_py(p, v));
		}
	}
	fprintf(f, "</g>\n<rect x=\"%.1f\" y=\"%.1f\" width=\"%.1f\" height=\"%.1f\" fill=\"none\" stroke=\"black\"/>\n",
	        p->x, p->y, p->w, p->h);
	/* tick labels */
	if (p->xlog && !p->categories) {
		for (double d = ceil(log10(p->x0) - 1e-9); d <= log10(p->x1) + 1e-9; d += 1) {
			char label[32];
			svg_decade_label(label, sizeof(label), d);
			fprintf(f, "<text x=\"%.1f\" y=\"%.1f\" text-anchor=\"middle\">%s</text>\n", svg_px(p, pow(10, d)),
			        p->y + p->h + 17, label);
		}
	} else if (!p->categories) {
		for (int i = 0; i <= 4; ++i) {
			const double v = p->x0 + (p->x1 - p->x0) * i / 4;
			fprintf(f, "<text x=\"%.1f\" y=\"%.1f\" text-anchor=\"middle\">%g</text>\n", svg_px(p, v),
			        p->y + p->h + 17, v);
		}
	}
	if (p->ylog) {
		for (double d = ceil(log10(p->y0) - 1e-9); d <= log10(p->y1) + 1e-9; d += 1) {
			char label[32];
			svg_decade_label(label, sizeof(label), d);
			fprintf(f, "<text x=\"%.1f\" y=\"%.1f\" text-anchor=\"end\">%s</text>\n", p->x - 6,
			        svg_py(p, pow(10, d)) + 4, label);
		}
	} else {
		for (int i = 0; i <= 4; ++i) {
			const double v = p->y0 + (p->y1 - p->y0) * i / 4;
			fprintf(f, "<text x=\"%.1f\" y=\"%.1f\" text-anchor=\"end\">%g</text>\n", p->x - 6, svg_py(p, v) + 4,
			        v);
		}
	}
	fprintf(f, "<text x=\"%.1f\" y=\"%.1f\" text-anchor=\"middle\">%s</text>\n", p->x + p->w / 2, p->y + p->h + 36,
	        xlabel);
	fprintf(f, "<text transform=\"translate(%.1f %.1f) rotate(-90)\" text-anchor=\"middle\">%s</text>\n", p->x - 50,
	        p->y + p->h / 2, ylabel);
	if (title && *title)
		fprintf(f, "<text x=\"%.1f\" y=\"%.1f\" text-anchor=\"middle\" font-weight=\"bold\">%s</text>\n",
		        p->x + p->w / 2, p->y - 8, title);
}

/* A cumulative histogram of n sorted values: fraction of values <= x. */
static inline void svg_cumulative(FILE* f, const svg_panel* p, const double* sorted, size_t n, int series)
{
	if (!n)
		return;
	fprintf(f, "<polyline fill=\"none\" stroke=\"%s\" stroke-width=\"1.8\" stroke-dasharray=\"%s\" points=\"",
	        svg_colours[series % SVG_SERIES_MAX], svg_dashes[series % SVG_SERIES_MAX]);
	fprintf(f, "%.1f,%.1f", svg_px(p, p->x0), svg_py(p, 0));
	/* At most ~400 points: the curve's steps are finer than a pixel anyway. */
	const size_t step = n > 400 ? n / 400 : 1;
	for (size_t i = 0; i < n; i += step)
		fprintf(f, " %.1f,%.1f", svg_px(p, sorted[i] > p->x0 ? sorted[i] : p->x0), svg_py(p, (double)(i + 1) / n));
	fprintf(f, " %.1f,%.1f", svg_px(p, sorted[n - 1]), svg_py(p, 1.0));
	fprintf(f, " %.1f,%.1f\"/>\n", svg_px(p, p->x1), svg_py(p, 1.0));
}

/* A line through n points (x[i], y[i]) with a dot at each. */
static inline void svg_line(FILE* f, const svg_panel* p, const double* x, const double* y, int n, int series)
{
	const int c = series % SVG_SERIES_MAX;
	fprintf(f, "<polyline fill=\"none\" stroke=\"%s\" stroke-width=\"1.8\" stroke-dasharray=\"%s\" points=\"",
	        svg_colours[c], svg_dashes[c]);
	for (int i = 0; i < n; ++i)
		fprintf(f, "%s%.1f,%.1f", i ? " " : "", svg_px(p, x[i]), svg_py(p, y[i]));
	fprintf(f, "\"/>\n");
	for (int i = 0; i < n; ++i)
		fprintf(f, "<circle cx=\"%.1f\" cy=\"%.1f\" r=\"2.5\" fill=\"%s\"/>\n", svg_px(p, x[i]), svg_py(p, y[i]),
		        svg_colours[c]);
}

/* A legend box at (x, y), `width` wide: row i names series[i]. */
static inline void svg_legend_width(FILE* f, double x, double y, double width, const char* const* names,
                                    const int* series, int n)
{
	fprintf(f, "<rect x=\"%.1f\" y=\"%.1f\" width=\"%.0f\" height=\"%d\" fill=\"white\" stroke=\"#999999\"/>\n", x,
	        y, width, 18 * n + 8);
	for (int i = 0; i < n; ++i) {
		const double ly = y + 14 + 18 * i;
		const int c = series[i] % SVG_SERIES_MAX;
		fprintf(f,
		        "<line x1=\"%.1f\" y1=\"%.1f\" x2=\"%.1f\" y2=\"%.1f\" stroke=\"%s\" stroke-width=\"2.2\" "
		        "stroke-dasharray=\"%s\"/>\n<text x=\"%.1f\" y=\"%.1f\">%s</text>\n",
		        x + 6, ly - 4, x + 36, ly - 4, svg_colours[c], svg_dashes[c], x + 42, ly, names[i]);
	}
}

static inline void svg_legend(FILE* f, double x, double y, const char* const* names, const int* series, int n)
{
	svg_legend_width(f, x, y, 100, names, series, n);
}

/* A bar at category i of n in panel p, with its value printed above it. */
static inline void svg_bar(FILE* f, const svg_panel* p, int i, int n, double v, const char* label, int series)
{
	const double slot = p->w / n, bw = slot * 0.6;
	const double x = p->x + slot * i + (slot - bw) / 2, top = svg_py(p, v);
	fprintf(f, "<rect x=\"%.1f\" y=\"%.1f\" width=\"%.1f\" height=\"%.1f\" fill=\"%s\"/>\n", x, top, bw,
	        p->y + p->h - top, svg_colours[series % SVG_SERIES_MAX]);
	fprintf(f, "<text x=\"%.1f\" y=\"%.1f\" text-anchor=\"middle\">%.3g</text>\n", x + bw / 2, top - 4, v);
	fprintf(f, "<text x=\"%.1f\" y=\"%.1f\" text-anchor=\"middle\">%s</text>\n", x + bw / 2, p->y + p->h + 17, label);
}

#endif /* VN_TOOLS_SVGPLOT_H */
