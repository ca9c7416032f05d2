/* Heat maps -> people: src/vc/deploy/decode.py in C99 (see vc_decode.h). The steps are decode.py's, in its order and
 * with its arithmetic: where numpy compares in float32 (the peak tests, the thresholds) this does too, where it
 * computes in float64 this does, sums run in index order (decode.py sums in order for that reason), ties go the way
 * numpy's stable sorts and first-maximum searches send them, and a float -> integer conversion out of range gives
 * what numpy's gives on x86-64 (INT64_MIN). Compile with -ffp-contract=off (no fused multiply-adds). */
#include "vc_decode.h"

#include <math.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

enum { CENTRE = 0, FIRST_KEYPOINT = 1, MASK = 18, FIRST_HANDEDNESS = 19, OFFSET_X = 27, OFFSET_Y = 28, HEAD = 33,
       SIZE = 34 };
static const int HEAD_KEYPOINTS[5] = {0, 1, 2, 3, 4};
static const int ANKLE_KEYPOINTS[2] = {15, 16};
static const double PERSON_AREA = 0.18;      /* decode.py's PERSON_AREA */
static const double MERGED_PEAK_REACH = 0.5; /* decode.py's MERGED_PEAK_REACH */
static const double SIZE_UNIT_CELLS = 20.0;  /* heatmaps.py's SIZE_UNIT_CELLS */
static const double HEAD_HEIGHT_AGREEMENT = 1.15; /* decode.py's HEAD_HEIGHT_AGREEMENT */

/* ---- numpy's semantics where they differ from C's ---- */

/* x.astype(int64) on x86-64: truncation; NaN and out-of-range values give INT64_MIN. */
static int64_t np_int(double value) {
    if (!(value >= -9223372036854775808.0 && value < 9223372036854775808.0)) return INT64_MIN;
    return (int64_t)value;
}

static int64_t clamp_index(int64_t value, int64_t low, int64_t high) { /* np.minimum(np.maximum(v, low), high) */
    return value < low ? low : (value > high ? high : value);
}

/* np.argmin / np.argmax: the first extreme value, or the first NaN. */
static int np_argmin(const double *values, int count) {
    int best = 0;
    for (int i = 1; i < count && !isnan(values[best]); ++i)
        if (values[i] < values[best] || isnan(values[i])) best = i;
    return best;
}

static int np_argmax(const double *values, int count) {
    int best = 0;
    for (int i = 1; i < count && !isnan(values[best]); ++i)
        if (values[i] > values[best] || isnan(values[i])) best = i;
    return best;
}

static double cells_to_input(double cells, int stride) { return (cells + 0.5) * stride - 0.5; }

/* ---- scratch memory ---- */

static void *allocate(size_t count, size_t size) {
    if (count == 0) count = 1;
    if (count > SIZE_MAX / size) return NULL;
    return malloc(count * size);
}

/* ---- step 1: local maxima (decode.py's local_maxima, _maxima_in, _refine_many) ---- */

typedef struct {
    int map, row, column;
    float value;
    double x, y; /* sub-cell position */
} peak;

typedef struct {
    peak *items;
    size_t count, capacity;
} peak_list;

static int push_peak(peak_list *list, peak item) {
    if (list->count == list->capacity) {
        size_t capacity = list->capacity ? 2 * list->capacity : 64;
        peak *grown = capacity > SIZE_MAX / sizeof(peak) ? NULL : realloc(list->items, capacity * sizeof(peak));
        if (!grown) return VC_ERROR_MEMORY;
        list->items = grown;
        list->capacity = capacity;
    }
    list->items[list->count++] = item;
    return VC_OK;
}

typedef struct {
    int top, bottom, left, right; /* rows [top, bottom), columns [left, right) */
} window;

static float cell_or_minus_infinity(const float *map, int height, int width, int row, int column) {
    if (row < 0 || row >= height || column < 0 || column >= width) return -INFINITY;
    return map[(size_t)row * width + column];
}

/* The local maxima above threshold of maps[0..count) inside one window, in map then reading order: at least as high
 * as the neighbours after it in reading order and strictly higher than those before (a plateau yields its first
 * cell). Neighbours outside the map count as -inf, inside it as themselves even outside the window. */
static int maxima_in(const float *maps, int count, int height, int width, float threshold, window in,
                     peak_list *out) {
    for (int map = 0; map < count; ++map) {
        const float *m = maps + (size_t)map * height * width;
        for (int row = in.top; row < in.bottom; ++row) {
            for (int column = in.left; column < in.right; ++column) {
                float value = m[(size_t)row * width + column];
                if (!(value > threshold)) continue;
#define AROUND(dy, dx) cell_or_minus_infinity(m, height, width, row + (dy), column + (dx))
                if (!(value > AROUND(0, -1) && value >= AROUND(0, 1))) continue;
                if (!(value > AROUND(-1, 0) && value >= AROUND(1, 0))) continue;
                if (!(value > AROUND(-1, -1) && value >= AROUND(1, 1))) continue;
                if (!(value > AROUND(-1, 1) && value >= AROUND(1, -1))) continue;
#undef AROUND
                peak found = {map, row, column, value, 0.0, 0.0};
                if (push_peak(out, found) != VC_OK) return VC_ERROR_MEMORY;
            }
        }
    }
    return VC_OK;
}

/* A stable merge sort of count items of size bytes (equal items keep their order, as numpy's stable sorts do);
 * before(a, b): whether a goes before b. scratch: room for count items. */
static void stable_sort(void *items, void *scratch, size_t count, size_t size,
                        int (*before)(const void *, const void *)) {
    if (count < 2) return;
    size_t half = count / 2;
    char *base = items, *out = scratch;
    stable_sort(base, scratch, half, size, before);
    stable_sort(base + half * size, scratch, count - half, size, before);
    size_t i = 0, j = half, k = 0;
    while (i < half && j < count) {
        size_t from = before(base + j * size, base + i * size) ? j++ : i++;
        memcpy(out + k++ * size, base + from * size, size);
    }
    memcpy(out + k * size, base + i * size, (half - i) * size);
    k += half - i;
    memcpy(out + k * size, base + j * size, (count - j) * size);
    memcpy(items, scratch, count * size);
}

/* By map, then strongest first. */
static int peak_before(const void *a, const void *b) {
    const peak *p = a, *q = b;
    if (p->map != q->map) return p->map < q->map;
    return p->value > q->value;
}

/* The parabola's vertex along one axis, in float64 (no shift at the border or where the values do not curve
 * down). */
static double vertex_shift(double before, double value, double after, int inside) {
    double curvature = before - 2.0 * value + after;
    if (!(inside && curvature < 0)) return 0.0;
    double vertex = 0.5 * (before - after) / curvature;
    return vertex < -0.5 ? -0.5 : (vertex > 0.5 ? 0.5 : vertex);
}

static void refine(const float *map, int height, int width, int row, int column, double *x, double *y) {
    const float *line = map + (size_t)row * width;
    float value = line[column];
    int left = column > 0 ? column - 1 : 0, right = column + 1 < width ? column + 1 : width - 1;
    int up = row > 0 ? row - 1 : 0, down = row + 1 < height ? row + 1 : height - 1;
    *x = (double)column + vertex_shift(line[left], value, line[right], column > 0 && column < width - 1);
    *y = (double)row + vertex_shift(map[(size_t)up * width + column], value,
                                            map[(size_t)down * width + column], row > 0 && row < height - 1);
}

/* decode.py's local_maxima: the maxima of maps[0..count) in the windows, by map and strongest first, at most limit
 * a map (limit < 0: all), refined. */
static int local_maxima(const float *maps, int count, int height, int width, float threshold, const window *windows,
                        int window_count, long limit, peak_list *out) {
    out->count = 0;
    for (int w = 0; w < window_count; ++w)
        if (maxima_in(maps, count, height, width, threshold, windows[w], out) != VC_OK) return VC_ERROR_MEMORY;
    peak *scratch = allocate(out->count, sizeof(peak));
    if (!scratch) return VC_ERROR_MEMORY;
    stable_sort(out->items, scratch, out->count, sizeof(peak), peak_before);
    free(scratch);
    if (limit >= 0) {
        size_t kept = 0;
        long in_map = 0;
        for (size_t i = 0; i < out->count; ++i) {
            in_map = (i > 0 && out->items[i].map == out->items[i - 1].map) ? in_map + 1 : 0;
            if (in_map < limit) out->items[kept++] = out->items[i];
        }
        out->count = kept;
    }
    for (size_t i = 0; i < out->count; ++i) {
        peak *p = &out->items[i];
        refine(maps + (size_t)p->map * height * width, height, width, p->row, p->column, &p->x, &p->y);
    }
    return VC_OK;
}

/* ---- the decoding's state ---- */

typedef struct {
    const float *maps;
    int channels, height, width;
    const vc_decode_config *config;
    const float *heights; /* expected height per cell, or NULL */
} frame;

static const float *channel(const frame *f, int index) { return f->maps + (size_t)index * f->height * f->width; }

/* decode.py's heights_px_at: the expected height (input px) of a person centred at (x, y) cells. */
static double height_px_at(const frame *f, double x, double y) {
    if (!f->heights) return f->config->default_height_px;
    int64_t row = clamp_index(np_int(rint(y)), 0, f->height - 1);
    int64_t column = clamp_index(np_int(rint(x)), 0, f->width - 1);
    return (double)f->heights[(size_t)row * f->width + column];
}

/* decode.py's _size_cells: the size map's person height (cells) at cell c, at most VC_MAX_HEIGHT_PX. */
static double size_cells(const frame *f, size_t c) {
    double largest = log(VC_MAX_HEIGHT_PX / f->config->stride / SIZE_UNIT_CELLS);
    return SIZE_UNIT_CELLS * exp(fmin((double)channel(f, SIZE)[c], largest));
}

/* ---- step 1b: the pixels' votes (decode.py's _vote_centres) ---- */

/* The sum over the (2 radius + 1)^2 window around each cell of grid (rows x columns, zeros beyond its border), from
 * a summed-area table, as decode.py's _window_sums computes it (its radius clipped to the grid, which changes no
 * sum). table: room for (rows + 2 radius + 1) x (columns + 2 radius + 1) doubles. */
static void window_sums(const double *grid, size_t grid_stride, int rows, int columns, int64_t radius,
                        double *sums, size_t sums_stride, double *table) {
    int64_t row_radius = radius < rows ? radius : rows, column_radius = radius < columns ? radius : columns;
    size_t table_rows = (size_t)(rows + 2 * row_radius + 1), table_columns = (size_t)(columns + 2 * column_radius + 1);
    memset(table, 0, table_rows * table_columns * sizeof(double));
    for (int r = 0; r < rows; ++r)
        for (int c = 0; c < columns; ++c)
            table[(size_t)(r + row_radius + 1) * table_columns + (size_t)(c + column_radius + 1)] =
                grid[(size_t)r * grid_stride + c];
    for (size_t r = 1; r < table_rows; ++r)
        for (size_t c = 0; c < table_columns; ++c) table[r * table_columns + c] += table[(r - 1) * table_columns + c];
    for (size_t r = 0; r < table_rows; ++r)
        for (size_t c = 1; c < table_columns; ++c) table[r * table_columns + c] += table[r * table_columns + c - 1];
    size_t row_side = (size_t)(2 * row_radius + 1), column_side = (size_t)(2 * column_radius + 1);
    for (int r = 0; r < rows; ++r)
        for (int c = 0; c < columns; ++c) {
            size_t top = (size_t)r, bottom = (size_t)r + row_side, left = (size_t)c, right = (size_t)c + column_side;
            sums[(size_t)r * sums_stride + c] = table[bottom * table_columns + right] -
                                                table[top * table_columns + right] -
                                                table[bottom * table_columns + left] + table[top * table_columns + left];
        }
}

static int64_t max64(int64_t a, int64_t b) { return a > b ? a : b; }
static int64_t min64(int64_t a, int64_t b) { return a < b ? a : b; }

/* decode.py's _update_window_sums: the sums of the windows within two radii of (row, column), from the grid read
 * one radius further out. local: room for the read area's sums. */
static void update_window_sums(double *sums, const double *grid, int height, int width, int64_t radius, int row,
                               int column, double *local, double *table) {
    int64_t rows_start = max64(0, row - 2 * radius), rows_stop = min64(height, row + 2 * radius + 1);
    int64_t columns_start = max64(0, column - 2 * radius), columns_stop = min64(width, column + 2 * radius + 1);
    int64_t read_top = max64(0, rows_start - radius), read_bottom = min64(height, rows_stop + radius);
    int64_t read_left = max64(0, columns_start - radius), read_right = min64(width, columns_stop + radius);
    int read_rows = (int)(read_bottom - read_top), read_columns = (int)(read_right - read_left);
    window_sums(grid + (size_t)read_top * width + (size_t)read_left, (size_t)width, read_rows, read_columns, radius,
                local, (size_t)read_columns, table);
    for (int64_t r = rows_start; r < rows_stop; ++r)
        for (int64_t c = columns_start; c < columns_stop; ++c)
            sums[(size_t)r * width + (size_t)c] = local[(size_t)(r - read_top) * read_columns + (size_t)(c - read_left)];
}

static int compare_doubles(const void *a, const void *b) {
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

typedef struct {
    size_t count;       /* foreground cells */
    int *rows, *columns;
    double *voted_x, *voted_y; /* where each cell says its person's centre is (cells) */
} foreground;

typedef struct {
    double *x, *y, *score;
    int count;
    double *sized; /* step 5: each person's height from the size map (cells); NaN: the decoder's box */
} centre_list;

/* Step 1b. Peaks 0..peaks->count are the centre map's; moved ones get their votes' centre, and added ones are
 * appended to added (x, y). */
static int vote_centres(const frame *f, const foreground *fg, centre_list *peaks, double *added_x, double *added_y,
                        int *added_count) {
    const vc_decode_config *config = f->config;
    int height = f->height, width = f->width, n_peaks = peaks->count;
    size_t m_count = fg->count, cells = (size_t)height * width;
    const float *mask = channel(f, MASK);
    double separation = isnan(config->vote_separation) ? config->min_centre_separation : config->vote_separation;
    int status = VC_ERROR_MEMORY;
    double *share = allocate(m_count, sizeof(double)), *vote_heights = allocate(m_count, sizeof(double));
    int64_t *cell_x = allocate(m_count, sizeof(int64_t)), *cell_y = allocate(m_count, sizeof(int64_t));
    unsigned char *free_vote = allocate(m_count, 1);
    double *claimed = allocate((size_t)n_peaks, sizeof(double)), *peak_heights = allocate((size_t)n_peaks,
                                                                                          sizeof(double));
    unsigned char *unsupported = allocate((size_t)n_peaks, 1), *moved = allocate((size_t)n_peaks, 1);
    double *moved_x = allocate((size_t)n_peaks, sizeof(double)), *moved_y = allocate((size_t)n_peaks, sizeof(double));
    double *votes_map = NULL, *support = NULL, *local = NULL, *table = NULL, *ordered = NULL;
    *added_count = 0;
    if (!share || !vote_heights || !cell_x || !cell_y || !free_vote || !claimed || !peak_heights || !unsupported ||
        !moved || !moved_x || !moved_y)
        goto done;
    for (int n = 0; n < n_peaks; ++n) {
        peak_heights[n] = height_px_at(f, peaks->x[n], peaks->y[n]) / config->stride;
        claimed[n] = 0.0;
        moved[n] = 0;
    }
    size_t free_count = 0;
    for (size_t m = 0; m < m_count; ++m) {
        double vote_height = height_px_at(f, fg->voted_x[m], fg->voted_y[m]) / config->stride;
        vote_heights[m] = vote_height;
        share[m] = (double)mask[(size_t)fg->rows[m] * width + fg->columns[m]] /
                   (PERSON_AREA * (vote_height * vote_height));
        int claims = 0;
        for (int n = 0; n < n_peaks; ++n)
            if (hypot(fg->voted_x[m] - peaks->x[n], fg->voted_y[m] - peaks->y[n]) <= separation * peak_heights[n]) {
                claimed[n] += share[m];
                claims = 1;
            }
        cell_x[m] = np_int(rint(fg->voted_x[m]));
        cell_y[m] = np_int(rint(fg->voted_y[m]));
        free_vote[m] = !claims && cell_x[m] >= 0 && cell_x[m] < width && cell_y[m] >= 0 && cell_y[m] < height;
        free_count += free_vote[m];
    }
    for (int n = 0; n < n_peaks; ++n) unsupported[n] = claimed[n] < config->vote_support;
    if (free_count == 0) {
        status = VC_OK;
        goto done;
    }
    ordered = allocate(free_count, sizeof(double));
    if (!ordered) goto done;
    size_t k = 0;
    for (size_t m = 0; m < m_count; ++m)
        if (free_vote[m]) ordered[k++] = vote_heights[m];
    qsort(ordered, free_count, sizeof(double), compare_doubles);
    double median = free_count % 2 ? ordered[free_count / 2]
                                   : (ordered[free_count / 2 - 1] + ordered[free_count / 2]) / 2;
    double rounded = rint(separation * median);
    int64_t largest = height > width ? height : width;
    int64_t radius = rounded > (double)largest ? largest : (rounded < 1.0 ? 1 : (int64_t)rounded);
    size_t table_size = (size_t)(3 * height + 1) * (size_t)(3 * width + 1);
    votes_map = calloc(cells, sizeof(double));
    support = allocate(cells, sizeof(double));
    local = allocate(cells, sizeof(double));
    table = allocate(table_size, sizeof(double));
    if (!votes_map || !support || !local || !table) goto done;
    for (size_t m = 0; m < m_count; ++m)
        if (free_vote[m]) votes_map[(size_t)cell_y[m] * width + (size_t)cell_x[m]] += share[m];
    window_sums(votes_map, (size_t)width, height, width, radius, support, (size_t)width, table);
    for (int round = 0; round < config->max_people; ++round) {
        size_t best = 0; /* np.argmax: the first maximum, or the first NaN */
        for (size_t c = 0; c < cells; ++c) {
            if (isnan(support[c])) {
                best = c;
                break;
            }
            if (support[c] > support[best]) best = c;
        }
        if (support[best] < config->vote_support) break;
        int row = (int)(best / width), column = (int)(best % width);
        double sum_x = 0.0, sum_y = 0.0, sum_share = 0.0;
        int first = 1;
        for (size_t m = 0; m < m_count; ++m) {
            if (!free_vote[m] || llabs(cell_x[m] - column) > radius || llabs(cell_y[m] - row) > radius) continue;
            double product_x = fg->voted_x[m] * share[m], product_y = fg->voted_y[m] * share[m];
            if (first) {
                sum_x = product_x, sum_y = product_y, sum_share = share[m];
                first = 0;
            } else {
                sum_x += product_x, sum_y += product_y, sum_share += share[m];
            }
            votes_map[(size_t)cell_y[m] * width + (size_t)cell_x[m]] += -share[m];
            free_vote[m] = 0;
        }
        double centre_x = sum_x / sum_share, centre_y = sum_y / sum_share;
        update_window_sums(support, votes_map, height, width, radius, row, column, local, table);
        int blur = -1; /* the unsupported peak nearest the votes' centre within reach, not yet moved */
        double blur_reach = 0.0;
        for (int n = 0; n < n_peaks; ++n) {
            double reach = hypot(peaks->x[n] - centre_x, peaks->y[n] - centre_y) / peak_heights[n];
            if (unsupported[n] && reach <= MERGED_PEAK_REACH && !moved[n] && (blur < 0 || reach < blur_reach)) {
                blur = n;
                blur_reach = reach;
            }
        }
        if (blur >= 0) { /* applied after the loop: every round measures against the peaks as found */
            moved[blur] = 1;
            moved_x[blur] = centre_x;
            moved_y[blur] = centre_y;
        } else {
            added_x[*added_count] = centre_x;
            added_y[*added_count] = centre_y;
            ++*added_count;
        }
    }
    for (int n = 0; n < n_peaks; ++n)
        if (moved[n]) peaks->x[n] = moved_x[n], peaks->y[n] = moved_y[n], peaks->sized[n] = NAN;
    status = VC_OK;
done:
    free(moved_x), free(moved_y);
    free(share), free(vote_heights), free(cell_x), free(cell_y), free(free_vote), free(claimed), free(peak_heights);
    free(unsupported), free(moved), free(votes_map), free(support), free(local), free(table), free(ordered);
    return status;
}

/* ---- step 2: keypoints ---- */

static double expected_row(const vc_decode_config *config, double centre_y, double height_cells, int keypoint) {
    return centre_y + config->prior_offsets[keypoint] * height_cells;
}

/* decode.py's _search_windows: the cells holding every peak within reach of one of the people's expected keypoint
 * positions, as column spans merged where they meet. Returns how many windows it wrote. */
static int search_windows(const frame *f, const double *x, const double *y, const double *heights_cells,
                          const double *reach, int count, window *windows, int *order) {
    int height = f->height, width = f->width;
    int64_t *spans = allocate((size_t)count * 4, sizeof(int64_t));
    if (!spans) return -1;
    for (int n = 0; n < count; ++n) {
        double margin = reach[n] + 0.5, lowest = INFINITY, highest = -INFINITY;
        for (int k = 0; k < VC_KEYPOINTS; ++k) {
            double row = expected_row(f->config, y[n], heights_cells[n], k);
            lowest = row < lowest ? row : lowest;
            highest = row > highest ? row : highest;
        }
        spans[4 * n + 0] = clamp_index(np_int(floor(x[n] - margin)), 0, width);
        spans[4 * n + 1] = clamp_index(np_int(ceil(x[n] + margin)) + 1, 0, width);
        spans[4 * n + 2] = clamp_index(np_int(floor(lowest - margin)), 0, height);
        spans[4 * n + 3] = clamp_index(np_int(ceil(highest + margin)) + 1, 0, height);
    }
    for (int n = 0; n < count; ++n) { /* a stable insertion sort by span start (a handful of people) */
        int j = n;
        while (j > 0 && spans[4 * order[j - 1]] > spans[4 * n]) {
            order[j] = order[j - 1];
            --j;
        }
        order[j] = n;
    }
    int written = 0;
    for (int i = 0; i < count; ++i) {
        const int64_t *s = spans + 4 * order[i];
        if (s[0] >= s[1] || s[2] >= s[3]) continue;
        if (written && s[0] <= windows[written - 1].right) {
            window *last = &windows[written - 1];
            last->top = (int)min64(last->top, s[2]);
            last->bottom = (int)max64(last->bottom, s[3]);
            last->right = (int)max64(last->right, s[1]);
        } else {
            window w = {(int)s[2], (int)s[3], (int)s[0], (int)s[1]};
            windows[written++] = w;
        }
    }
    free(spans);
    return written;
}

typedef struct {
    double score;
    size_t index; /* person * peaks + peak: the order of equal scores */
} candidate;

static int candidate_before(const void *a, const void *b) {
    return ((const candidate *)a)->score > ((const candidate *)b)->score;
}

/* decode.py's _exclusive_keypoints: keypoint peaks shared out among the strong people, best prior-weighted value
 * first, one person a peak. keypoints: count x 17 x 3. */
static int exclusive_keypoints(const frame *f, const double *x, const double *y, const double *heights_cells,
                               int count, double *keypoints) {
    const vc_decode_config *config = f->config;
    int height = f->height, width = f->width, status = VC_ERROR_MEMORY;
    const float *maps = channel(f, FIRST_KEYPOINT);
    double *sigmas = allocate((size_t)count, sizeof(double)), *reach = allocate((size_t)count, sizeof(double));
    window *windows = allocate((size_t)count, sizeof(window));
    int *order = allocate((size_t)count, sizeof(int));
    unsigned char *slot_taken = allocate((size_t)count * VC_KEYPOINTS, 1), *peak_taken = NULL;
    candidate *candidates = NULL, *scratch = NULL;
    peak_list peaks = {NULL, 0, 0};
    memset(keypoints, 0, (size_t)count * VC_KEYPOINTS * 3 * sizeof(double));
    if (!sigmas || !reach || !windows || !order || !slot_taken) goto done;
    for (int n = 0; n < count; ++n) {
        sigmas[n] = config->search_sigma * heights_cells[n];
        reach[n] = 3.0 * sigmas[n];
    }
    int window_count = search_windows(f, x, y, heights_cells, reach, count, windows, order);
    if (window_count < 0) goto done;
    if (local_maxima(maps, VC_KEYPOINTS, height, width, (float)config->keypoint_peak_floor, windows, window_count,
                     4L * count + 8, &peaks) != VC_OK)
        goto done;
    size_t peak_count = peaks.count, pairs = (size_t)count * peak_count;
    candidates = allocate(pairs, sizeof(candidate));
    scratch = allocate(pairs, sizeof(candidate));
    peak_taken = calloc(peak_count ? peak_count : 1, 1);
    if (!candidates || !scratch || !peak_taken) goto done;
    size_t candidate_count = 0;
    for (int n = 0; n < count; ++n)
        for (size_t p = 0; p < peak_count; ++p) {
            const peak *q = &peaks.items[p];
            double expected_x = x[n], expected_y = expected_row(config, y[n], heights_cells[n], q->map);
            double offset_x = q->x - expected_x, offset_y = q->y - expected_y;
            int on_map = expected_y > -0.5 && expected_y < height - 0.5;
            int near = fabs(offset_x) <= reach[n] && fabs(offset_y) <= reach[n] && on_map;
            double score = near ? (double)q->value * exp(-(offset_x * offset_x + offset_y * offset_y) /
                                                         (2.0 * (sigmas[n] * sigmas[n])))
                                : 0.0;
            if (score > 0.0) {
                candidate c = {score, (size_t)n * peak_count + p};
                candidates[candidate_count++] = c;
            }
        }
    stable_sort(candidates, scratch, candidate_count, sizeof(candidate), candidate_before);
    memset(slot_taken, 0, (size_t)count * VC_KEYPOINTS);
    for (size_t i = 0; i < candidate_count; ++i) {
        size_t person = candidates[i].index / peak_count, p = candidates[i].index % peak_count;
        const peak *q = &peaks.items[p];
        unsigned char *slot = &slot_taken[person * VC_KEYPOINTS + (size_t)q->map];
        if (*slot || peak_taken[p]) continue;
        *slot = 1;
        peak_taken[p] = 1;
        double *keypoint = keypoints + (person * VC_KEYPOINTS + (size_t)q->map) * 3;
        keypoint[0] = cells_to_input(q->x, config->stride);
        keypoint[1] = cells_to_input(q->y, config->stride);
        keypoint[2] = (double)q->value;
    }
    for (int n = 0; n < count; ++n) /* a person without a peak: the upright position, the map's value there */
        for (int k = 0; k < VC_KEYPOINTS; ++k) {
            double expected_y = expected_row(config, y[n], heights_cells[n], k);
            if (slot_taken[(size_t)n * VC_KEYPOINTS + k] || !(expected_y > -0.5 && expected_y < height - 0.5))
                continue;
            double *keypoint = keypoints + ((size_t)n * VC_KEYPOINTS + k) * 3;
            keypoint[0] = cells_to_input(x[n], config->stride);
            keypoint[1] = cells_to_input(expected_y, config->stride);
            int64_t column = clamp_index(np_int(rint(x[n])), 0, width - 1);
            int64_t row = clamp_index(np_int(rint(expected_y)), 0, height - 1);
            keypoint[2] = (double)maps[((size_t)k * height + (size_t)row) * width + (size_t)column];
        }
    status = VC_OK;
done:
    free(sigmas), free(reach), free(windows), free(order), free(slot_taken), free(peak_taken), free(candidates);
    free(scratch), free(peaks.items);
    return status;
}

/* decode.py's _keypoints (weak people): each keypoint the maximum of its map times the person's upright prior,
 * within 3 prior widths of the expected position. keypoints: 17 x 3 of one person. */
static void own_keypoints(const frame *f, double x, double y, double height_cells, double *keypoints) {
    const vc_decode_config *config = f->config;
    int height = f->height, width = f->width;
    double sigma = config->search_sigma * height_cells;
    int64_t reach = np_int(ceil(3.0 * sigma)), centre_column = np_int(rint(x));
    int64_t x0 = max64(centre_column - reach, 0), x1 = min64(centre_column + reach + 1, width);
    memset(keypoints, 0, VC_KEYPOINTS * 3 * sizeof(double));
    for (int k = 0; k < VC_KEYPOINTS; ++k) {
        double expected = expected_row(config, y, height_cells, k);
        int64_t start = max64(np_int(rint(expected)) - reach, 0), stop = min64(np_int(rint(expected)) + reach + 1,
                                                                                height);
        if (!(start < stop && x0 < x1)) continue;
        const float *map = channel(f, FIRST_KEYPOINT + k);
        double best = -INFINITY;
        int64_t best_row = start, best_column = x0;
        for (int64_t row = start; row < stop; ++row) {
            double dy = (double)row - expected;
            double prior_y = exp(-(dy * dy) / (2.0 * (sigma * sigma)));
            for (int64_t column = x0; column < x1; ++column) {
                double dx = (double)column - x;
                double prior_x = exp(-(dx * dx) / (2.0 * (sigma * sigma)));
                double weighted = (double)map[(size_t)row * width + (size_t)column] * (prior_y * prior_x);
                if (weighted > best) { /* the first maximum in reading order (finite maps: no NaN) */
                    best = weighted;
                    best_row = row;
                    best_column = column;
                }
            }
        }
        double peak_x, peak_y;
        refine(map, height, width, (int)best_row, (int)best_column, &peak_x, &peak_y);
        keypoints[3 * k + 0] = cells_to_input(peak_x, config->stride);
        keypoints[3 * k + 1] = cells_to_input(peak_y, config->stride);
        keypoints[3 * k + 2] = (double)map[(size_t)best_row * width + (size_t)best_column];
    }
}

/* ---- step 4: the box (decode.py's _boxes, one person) ---- */

static void person_box(const vc_decode_config *config, const double *centre, double height_px, const double *keypoints,
                       int64_t first_column, int64_t last_column, int has_mask, double *box) {
    double lowest = INFINITY, highest = -INFINITY;
    int confident[VC_KEYPOINTS];
    for (int k = 0; k < VC_KEYPOINTS; ++k) {
        double x = keypoints[3 * k];
        confident[k] = keypoints[3 * k + 2] >= config->keypoint_threshold;
        if (confident[k] && fabs(x - centre[0]) <= config->reach_sideways * height_px) {
            lowest = x < lowest ? x : lowest;
            highest = x > highest ? x : highest;
        }
    }
    if (has_mask) {
        double first = cells_to_input((double)first_column - 0.5, config->stride);
        double last = cells_to_input((double)last_column + 0.5, config->stride);
        lowest = first < lowest ? first : lowest;
        highest = last > highest ? last : highest;
    }
    if (!isfinite(lowest)) lowest = centre[0], highest = centre[0];
    double margin = config->side_margin * height_px, half_min = config->min_width * height_px / 2;
    double left = centre[0] - lowest + margin, right = highest - centre[0] + margin;
    left = left >= half_min ? left : half_min;
    right = right >= half_min ? right : half_min;
    double top = centre[1] - height_px / 2, bottom = centre[1] + height_px / 2;
    double heads[5], ankles[2];
    int any_head = 0, any_ankle = 0;
    for (int i = 0; i < 5; ++i) {
        int k = HEAD_KEYPOINTS[i];
        heads[i] = confident[k] ? keypoints[3 * k + 1] : INFINITY;
        any_head |= confident[k];
    }
    for (int i = 0; i < 2; ++i) {
        int k = ANKLE_KEYPOINTS[i];
        ankles[i] = confident[k] ? keypoints[3 * k + 1] : -INFINITY;
        any_ankle |= confident[k];
    }
    int head = HEAD_KEYPOINTS[np_argmin(heads, 5)], ankle = ANKLE_KEYPOINTS[np_argmax(ankles, 2)];
    double head_y = keypoints[3 * head + 1], ankle_y = keypoints[3 * ankle + 1];
    double height = (ankle_y - head_y) / (config->prior_lower_ankle - config->prior_offsets[head]);
    double ratio = height / height_px;
    if (any_head && any_ankle && 1.0 / config->keypoint_height_range <= ratio &&
        ratio <= config->keypoint_height_range) {
        double keypoint_top = head_y - (0.5 + config->prior_offsets[head]) * height;
        top = keypoint_top;
        bottom = keypoint_top + height;
    }
    box[0] = centre[0] - left;
    box[1] = top;
    box[2] = centre[0] + right;
    box[3] = bottom;
}

/* ---- the whole decoding ---- */

const char *vc_status_message(int status) {
    switch (status) {
    case VC_OK: return "ok";
    case VC_ERROR_ARGUMENT: return "invalid argument";
    case VC_ERROR_ANATOMICAL: return "heat maps in the retired layout of 19 maps (pairs in anatomical order)";
    case VC_ERROR_LAYOUT: return "heat maps in none of the layouts of 27, 29, 33 or 35 maps";
    case VC_ERROR_NOT_FINITE: return "heat maps hold NaN or infinite values";
    case VC_ERROR_HEIGHTS: return "expected heights must be finite and within (0, 100000] px";
    case VC_ERROR_MEMORY: return "out of memory";
    case VC_ERROR_FILE: return "the decoder file cannot be read";
    case VC_ERROR_FORMAT: return "the decoder file is malformed or of another version";
    default: return "unknown status";
    }
}

static int separated(const double *x, const double *y, const double *heights_cells, int count, double separation,
                     int *kept) {
    int kept_count = 0;
    for (int i = 0; i < count; ++i) {
        int apart = 1;
        for (int j = 0; j < kept_count && apart; ++j) {
            int other = kept[j];
            apart = hypot(x[i] - x[other], y[i] - y[other]) >= separation * heights_cells[other];
        }
        if (apart) kept[kept_count++] = i;
    }
    return kept_count;
}

/* Steps 1-4 on the centre map's peaks, or (from_heads, step 5) on the head map's: people[0..*count), and each
 * foreground cell's strong and weak owner where those are given. */
static int read_people(const frame *source, double floor_value, int from_heads, vc_person *people, int *count,
                       int32_t *strong_owner, int32_t *weak_owner) {
    const frame f = *source;
    const vc_decode_config *config = f.config;
    int height = f.height, width = f.width, channels = f.channels;
    size_t cells = (size_t)height * width;
    int stride = config->stride, max_people = config->max_people, status = VC_ERROR_MEMORY;
    peak_list found = {NULL, 0, 0};
    foreground fg = {0, NULL, NULL, NULL, NULL};
    size_t capacity_people = (size_t)max_people;
    double *x = allocate(capacity_people, sizeof(double)), *y = allocate(capacity_people, sizeof(double));
    double *heights_px = allocate(capacity_people, sizeof(double));
    double *score = allocate(capacity_people, sizeof(double)), *heights_cells = allocate(capacity_people,
                                                                                          sizeof(double));
    double *sized = allocate(capacity_people, sizeof(double));
    double *added_x = allocate(capacity_people, sizeof(double)), *added_y = allocate(capacity_people, sizeof(double));
    int *kept = allocate(capacity_people, sizeof(int)), *strong_index = allocate(capacity_people, sizeof(int));
    double *keypoints = allocate(capacity_people * VC_KEYPOINTS * 3, sizeof(double));
    double *strong_x = allocate(capacity_people, sizeof(double)), *strong_y = allocate(capacity_people,
                                                                                       sizeof(double));
    double *strong_heights = allocate(capacity_people, sizeof(double));
    double *strong_keypoints = allocate(capacity_people * VC_KEYPOINTS * 3, sizeof(double));
    unsigned char *strong = allocate(capacity_people, 1);
    int32_t *owner = NULL, *owner_among_strong = NULL;
    int64_t *first_column = allocate(capacity_people, sizeof(int64_t)), *last_column = allocate(capacity_people,
                                                                                               sizeof(int64_t));
    if (!x || !y || !heights_px || !score || !heights_cells || !sized || !added_x || !added_y || !kept ||
        !strong_index || !keypoints || !strong_x || !strong_y || !strong_heights || !strong_keypoints || !strong ||
        !first_column || !last_column)
        goto done;

    /* Step 1: the centre map's peaks, the strongest max_people, those too near a stronger one dropped; step 5:
     * the head map's, none dropped, each moved to its person's centre by the offset times the size map's height. */
    window whole = {0, height, 0, width};
    const float *centre_map = channel(&f, from_heads ? HEAD : CENTRE);
    if (local_maxima(centre_map, 1, height, width, (float)floor_value, &whole, 1, max_people, &found) != VC_OK)
        goto done;
    int found_count = (int)found.count, n;
    if (from_heads) {
        for (int i = 0; i < found_count; ++i) {
            size_t c = (size_t)clamp_index(np_int(rint(found.items[i].y)), 0, height - 1) * width +
                       (size_t)clamp_index(np_int(rint(found.items[i].x)), 0, width - 1);
            sized[i] = size_cells(&f, c);
            double centre_x = found.items[i].x + (double)channel(&f, OFFSET_X)[c] * sized[i];
            double centre_y = found.items[i].y + (double)channel(&f, OFFSET_Y)[c] * sized[i];
            x[i] = centre_x < 0.0 ? 0.0 : (centre_x > width - 1 ? (double)(width - 1) : centre_x);
            y[i] = centre_y < 0.0 ? 0.0 : (centre_y > height - 1 ? (double)(height - 1) : centre_y);
            score[i] = (double)found.items[i].value;
        }
        n = found_count;
    } else {
        for (int i = 0; i < found_count; ++i) {
            x[i] = found.items[i].x;
            y[i] = found.items[i].y;
            heights_cells[i] = height_px_at(&f, x[i], y[i]) / stride;
        }
        n = separated(x, y, heights_cells, found_count, config->min_centre_separation, kept);
        for (int i = 0; i < n; ++i) {
            score[i] = (double)found.items[kept[i]].value;
            x[i] = found.items[kept[i]].x;
            y[i] = found.items[kept[i]].y;
            sized[i] = NAN;
        }
    }

    /* The mask's cells and where each votes for its person's centre (step 1b); without offsets, the cell itself. */
    const float *mask = channel(&f, MASK);
    float mask_threshold = (float)config->mask_threshold;
    for (size_t c = 0; c < cells; ++c) fg.count += mask[c] > mask_threshold;
    fg.rows = allocate(fg.count, sizeof(int));
    fg.columns = allocate(fg.count, sizeof(int));
    fg.voted_x = allocate(fg.count, sizeof(double));
    fg.voted_y = allocate(fg.count, sizeof(double));
    owner = allocate(fg.count, sizeof(int32_t));
    owner_among_strong = allocate(fg.count, sizeof(int32_t));
    if (!fg.rows || !fg.columns || !fg.voted_x || !fg.voted_y || !owner || !owner_among_strong) goto done;
    size_t m = 0;
    for (size_t c = 0; c < cells; ++c)
        if (mask[c] > mask_threshold) {
            fg.rows[m] = (int)(c / width);
            fg.columns[m] = (int)(c % width);
            fg.voted_x[m] = fg.columns[m];
            fg.voted_y[m] = fg.rows[m];
            ++m;
        }
    if (channels >= VC_LAYOUT_OFFSETS && fg.count) {
        const float *offset_x = channel(&f, OFFSET_X), *offset_y = channel(&f, OFFSET_Y);
        for (m = 0; m < fg.count; ++m) {
            size_t c = (size_t)fg.rows[m] * width + fg.columns[m];
            double scale = from_heads ? size_cells(&f, c) : height_px_at(&f, fg.voted_x[m], fg.voted_y[m]) / stride;
            fg.voted_x[m] += (double)offset_x[c] * scale;
            fg.voted_y[m] += (double)offset_y[c] * scale;
        }
        centre_list peaks = {x, y, score, n, sized};
        int added = 0;
        if (vote_centres(&f, &fg, &peaks, added_x, added_y, &added) != VC_OK) goto done;
        for (int a = 0; a < added; ++a) {
            int64_t column = clamp_index(np_int(rint(added_x[a])), 0, width - 1);
            int64_t row = clamp_index(np_int(rint(added_y[a])), 0, height - 1);
            double value = (double)centre_map[(size_t)row * width + (size_t)column];
            if (value >= floor_value && n < max_people) {
                score[n] = value;
                x[n] = added_x[a];
                y[n] = added_y[a];
                sized[n] = NAN;
                ++n;
            }
        }
    }
    if (n == 0) {
        status = VC_OK;
        goto done;
    }

    int strong_count = 0;
    for (int i = 0; i < n; ++i) {
        heights_px[i] = height_px_at(&f, x[i], y[i]);
        heights_cells[i] = heights_px[i] / stride;
        strong[i] = score[i] >= config->centre_threshold;
        if (strong[i]) strong_index[strong_count++] = i;
    }
    /* Step 3's owners: each foreground cell's nearest centre (to its vote, in expected heights), and its nearest
     * strong one (np.argmin: the first minimum, or the first NaN). */
    for (m = 0; m < fg.count; ++m) {
        double best = 0.0, best_strong = 0.0;
        int32_t nearest = 0, nearest_strong = -1;
        for (int i = 0; i < n; ++i) {
            double scaled = hypot(fg.voted_x[m] - x[i], fg.voted_y[m] - y[i]) / heights_cells[i];
            if (i == 0 || (!isnan(best) && (scaled < best || isnan(scaled)))) best = scaled, nearest = i;
            if (strong[i] && (nearest_strong < 0 || (!isnan(best_strong) && (scaled < best_strong || isnan(scaled)))))
                best_strong = scaled, nearest_strong = i;
        }
        owner[m] = nearest;
        owner_among_strong[m] = strong_count ? nearest_strong : nearest;
    }

    /* Step 2: strong people share out the keypoint peaks; weak ones search their own. */
    for (int s = 0; s < strong_count; ++s) {
        strong_x[s] = x[strong_index[s]];
        strong_y[s] = y[strong_index[s]];
        strong_heights[s] = heights_cells[strong_index[s]];
    }
    if (exclusive_keypoints(&f, strong_x, strong_y, strong_heights, strong_count, strong_keypoints) != VC_OK)
        goto done;
    for (int s = 0; s < strong_count; ++s)
        memcpy(keypoints + (size_t)strong_index[s] * VC_KEYPOINTS * 3, strong_keypoints + (size_t)s * VC_KEYPOINTS * 3,
               VC_KEYPOINTS * 3 * sizeof(double));
    for (int i = 0; i < n; ++i)
        if (!strong[i]) own_keypoints(&f, x[i], y[i], heights_cells[i], keypoints + (size_t)i * VC_KEYPOINTS * 3);

    for (int i = 0; i < n; ++i) {
        vc_person *person = &people[i];
        double *own = keypoints + (size_t)i * VC_KEYPOINTS * 3;
        int64_t row = np_int(rint(y[i])), column = np_int(rint(x[i])); /* numpy indexing: negative counts back */
        if (row < 0) row += height;
        if (column < 0) column += width;
        if (row < 0 || row >= height || column < 0 || column >= width) {
            status = VC_ERROR_ARGUMENT;
            goto done;
        }
        for (int p = 0; p < VC_PAIRS; ++p) {
            float handedness = channel(&f, FIRST_HANDEDNESS + p)[(size_t)row * width + (size_t)column];
            person->pair_handedness[p] = handedness;
            if (handedness < 0) { /* the pair's image-left member is the person's right one */
                double swap[3];
                double *left = own + 3 * (1 + 2 * p), *right = own + 3 * (2 + 2 * p);
                memcpy(swap, left, sizeof swap);
                memcpy(left, right, sizeof swap);
                memcpy(right, swap, sizeof swap);
            }
        }
        first_column[i] = INT64_MAX;
        last_column[i] = -1;
    }
    /* Step 3: a cell belongs to its owner within reach (a strong person's owner among the strong). */
    for (m = 0; m < fg.count; ++m) {
        size_t c = (size_t)fg.rows[m] * width + fg.columns[m];
        for (int which = 0; which < 2; ++which) {
            int32_t i = which == 0 ? owner_among_strong[m] : owner[m];
            if (which == 0 ? !strong[i] : strong[i]) continue;
            if (!(fabs((double)fg.columns[m] - x[i]) <= config->reach_sideways * heights_cells[i] &&
                  fabs((double)fg.rows[m] - y[i]) <= config->reach_vertical * heights_cells[i]))
                continue;
            if (which == 0 && strong_owner) strong_owner[c] = i;
            if (which == 1 && weak_owner) weak_owner[c] = i;
            first_column[i] = fg.columns[m] < first_column[i] ? fg.columns[m] : first_column[i];
            last_column[i] = fg.columns[m] > last_column[i] ? fg.columns[m] : last_column[i];
        }
    }
    for (int i = 0; i < n; ++i) {
        vc_person *person = &people[i];
        person->score = score[i];
        person->centre[0] = cells_to_input(x[i], stride);
        person->centre[1] = cells_to_input(y[i], stride);
        memcpy(person->keypoints, keypoints + (size_t)i * VC_KEYPOINTS * 3, VC_KEYPOINTS * 3 * sizeof(double));
        person_box(config, person->centre, heights_px[i], &person->keypoints[0][0], first_column[i],
                   last_column[i], last_column[i] >= 0, person->box);
        if (isfinite(sized[i])) { /* step 5: the size map's height, centred on the centre, where step 4's disagrees */
            double ratio = (person->box[3] - person->box[1]) / (sized[i] * stride);
            if (!(ratio >= 1.0 / HEAD_HEIGHT_AGREEMENT && ratio <= HEAD_HEIGHT_AGREEMENT)) {
                person->box[1] = person->centre[1] - sized[i] * stride / 2;
                person->box[3] = person->centre[1] + sized[i] * stride / 2;
            }
        }
        person->weak = !strong[i];
        person->head_found = 0;
    }
    *count = n;
    status = VC_OK;
done:
    free(found.items), free(fg.rows), free(fg.columns), free(fg.voted_x), free(fg.voted_y), free(owner);
    free(owner_among_strong), free(x), free(heights_px), free(y), free(score), free(heights_cells), free(sized);
    free(added_x), free(added_y);
    free(kept), free(strong_index), free(keypoints), free(strong_x), free(strong_y), free(strong_heights);
    free(strong_keypoints), free(strong), free(first_column), free(last_column);
    return status;
}

/* ---- step 5: the people read from the heads ---- */

/* Steps 1-4 on the centre map, then on the head map: its strong people appended, flagged head_found, each with the
 * cells the head reading gives them in head_owner (decode.py's decode_readings). */
static int read_with_heads(const frame *f, double floor_value, vc_person *people, int *count, int32_t *strong_owner,
                           int32_t *weak_owner, int32_t *head_owner) {
    size_t cells = (size_t)f->height * f->width, capacity = (size_t)f->config->max_people;
    int status = VC_ERROR_MEMORY, first = 0, found = 0;
    int32_t *found_owner = allocate(cells, sizeof(int32_t));
    vc_person *heads = allocate(capacity, sizeof(vc_person));
    int *kept_as = allocate(capacity, sizeof(int));
    if (!found_owner || !heads || !kept_as) goto done;
    for (size_t c = 0; c < cells; ++c) found_owner[c] = -1;
    if ((status = read_people(f, floor_value, 0, people, &first, strong_owner, weak_owner)) != VC_OK) goto done;
    if ((status = read_people(f, floor_value, 1, heads, &found, found_owner, NULL)) != VC_OK) goto done;
    int total = first;
    for (int k = 0; k < found; ++k) {
        kept_as[k] = -1;
        if (heads[k].weak) continue;
        people[total] = heads[k];
        people[total].head_found = 1;
        kept_as[k] = total++;
    }
    if (head_owner)
        for (size_t c = 0; c < cells; ++c) head_owner[c] = found_owner[c] >= 0 ? kept_as[found_owner[c]] : -1;
    *count = total;
    status = VC_OK;
done:
    free(found_owner), free(heads), free(kept_as);
    return status;
}

int vc_decode(const float *heatmaps, int channels, int height, int width, const vc_decode_config *config,
              const float *expected_height_px, double weak_above, vc_person *people, int capacity, int *count,
              int32_t *strong_owner, int32_t *weak_owner, int32_t *head_owner) {
    if (!heatmaps || !config || !people || !count || height < 0 || width < 0 || config->stride < 1 ||
        config->max_people < 0 || capacity < config->max_people ||
        (channels == VC_LAYOUT_HEAD && capacity - config->max_people < config->max_people))
        return VC_ERROR_ARGUMENT;
    *count = 0;
    if (channels == VC_LAYOUT_ANATOMICAL) return VC_ERROR_ANATOMICAL;
    if (channels != VC_LAYOUT_HANDEDNESS && channels != VC_LAYOUT_OFFSETS && channels != VC_LAYOUT_FINE &&
        channels != VC_LAYOUT_HEAD)
        return VC_ERROR_LAYOUT;
    if (width > 0 && (size_t)height > SIZE_MAX / sizeof(double) / 16 / (size_t)width) return VC_ERROR_MEMORY;
    size_t cells = (size_t)height * width;
    for (size_t i = 0; i < cells * (size_t)channels; ++i)
        if (!isfinite(heatmaps[i])) return VC_ERROR_NOT_FINITE;
    if (expected_height_px)
        for (size_t i = 0; i < cells; ++i)
            if (!(expected_height_px[i] > 0.0f && expected_height_px[i] <= VC_MAX_HEIGHT_PX)) return VC_ERROR_HEIGHTS;
    if (strong_owner)
        for (size_t i = 0; i < cells; ++i) strong_owner[i] = -1;
    if (weak_owner)
        for (size_t i = 0; i < cells; ++i) weak_owner[i] = -1;
    if (head_owner)
        for (size_t i = 0; i < cells; ++i) head_owner[i] = -1;
    if (cells == 0) return VC_OK;

    frame f = {heatmaps, channels, height, width, config, expected_height_px};
    double floor_value = isnan(weak_above) || !(weak_above < config->centre_threshold) ? config->centre_threshold
                                                                                       : weak_above;
    if (channels != VC_LAYOUT_HEAD)
        return read_people(&f, floor_value, 0, people, count, strong_owner, weak_owner);
    return read_with_heads(&f, floor_value, people, count, strong_owner, weak_owner, head_owner);
}
