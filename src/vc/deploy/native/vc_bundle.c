/* The bundle's flat decoder file (decoder.txt; its format: src/vc/deploy/decoder_file.py), read without a JSON
 * parser: whitespace-separated tokens, each record a keyword and its values in a fixed order. Anything else (another
 * version, a missing or extra value, a number out of range, a truncated file) is refused with the line at fault. */
#include "vc_decode.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define MAX_FILE_BYTES (256L * 1024 * 1024)
#define MAX_CELLS (16L * 1024 * 1024)

typedef struct {
    char *text;
    size_t at, size;
    int line;
    char token[128];
} reader;

/* The next token into r->token; 0 at the end of the file or for a token too long. */
static int next_token(reader *r) {
    while (r->at < r->size && (r->text[r->at] == ' ' || r->text[r->at] == '\t' || r->text[r->at] == '\n' ||
                               r->text[r->at] == '\r')) {
        if (r->text[r->at] == '\n') ++r->line;
        ++r->at;
    }
    size_t length = 0;
    while (r->at < r->size && r->text[r->at] != ' ' && r->text[r->at] != '\t' && r->text[r->at] != '\n' &&
           r->text[r->at] != '\r') {
        if (length + 1 >= sizeof r->token) return 0;
        r->token[length++] = r->text[r->at++];
    }
    r->token[length] = '\0';
    return length > 0;
}

static int keyword(reader *r, const char *expected) { return next_token(r) && strcmp(r->token, expected) == 0; }

static int read_double(reader *r, double *value) {
    if (!next_token(r)) return 0;
    char *end;
    errno = 0;
    *value = strtod(r->token, &end);
    return *end == '\0' && errno == 0 && isfinite(*value);
}

static int read_int(reader *r, long low, long high, int *value) {
    if (!next_token(r)) return 0;
    char *end;
    errno = 0;
    long parsed = strtol(r->token, &end, 10);
    if (*end != '\0' || errno != 0 || parsed < low || parsed > high) return 0;
    *value = (int)parsed;
    return 1;
}

static int field_double(reader *r, const char *name, double *value) { return keyword(r, name) && read_double(r, value); }

static int field_ints(reader *r, const char *name, int count, long low, long high, int *values) {
    if (!keyword(r, name)) return 0;
    for (int i = 0; i < count; ++i)
        if (!read_int(r, low, high, &values[i])) return 0;
    return 1;
}

static int read_config(reader *r, vc_decode_config *c) {
    if (!field_ints(r, "stride", 1, 1, 1024, &c->stride)) return 0;
    if (!field_double(r, "centre_threshold", &c->centre_threshold)) return 0;
    if (!field_double(r, "keypoint_threshold", &c->keypoint_threshold)) return 0;
    if (!field_double(r, "mask_threshold", &c->mask_threshold)) return 0;
    if (!field_double(r, "search_sigma", &c->search_sigma)) return 0;
    if (!field_double(r, "default_height_px", &c->default_height_px)) return 0;
    if (!field_ints(r, "max_people", 1, 0, 100000, &c->max_people)) return 0;
    if (!field_double(r, "min_centre_separation", &c->min_centre_separation)) return 0;
    if (!field_double(r, "reach_sideways", &c->reach_sideways)) return 0;
    if (!field_double(r, "reach_vertical", &c->reach_vertical)) return 0;
    if (!field_double(r, "min_width", &c->min_width)) return 0;
    if (!field_double(r, "side_margin", &c->side_margin)) return 0;
    if (!field_double(r, "keypoint_height_range", &c->keypoint_height_range)) return 0;
    if (!field_double(r, "keypoint_peak_floor", &c->keypoint_peak_floor)) return 0;
    if (!field_double(r, "vote_support", &c->vote_support)) return 0;
    if (!keyword(r, "vote_separation")) return 0;
    size_t before = r->at;
    int line = r->line;
    if (next_token(r) && strcmp(r->token, "none") == 0) {
        c->vote_separation = NAN;
        return 1;
    }
    r->at = before, r->line = line;
    return read_double(r, &c->vote_separation);
}

static int read_region(reader *r, const double *offsets, double lower_ankle, vc_region *region) {
    if (!keyword(r, "region") || !next_token(r) || strlen(r->token) >= sizeof region->name) return 0;
    strcpy(region->name, r->token);
    if (!field_ints(r, "crop_window", 4, 0, 1000000, region->crop_window)) return 0;
    if (!field_ints(r, "input_size", 2, 1, 1000000, region->input_size)) return 0;
    if (!read_config(r, &region->config)) return 0;
    memcpy(region->config.prior_offsets, offsets, sizeof region->config.prior_offsets);
    region->config.prior_lower_ankle = lower_ankle;
    region->channels = 0;
    if (!field_ints(r, "expected_height", 2, 1, MAX_CELLS, region->heatmap_size)) return 0;
    long cells = (long)region->heatmap_size[0] * region->heatmap_size[1];
    if (cells > MAX_CELLS) return 0;
    region->expected_height_px = malloc((size_t)cells * sizeof(float));
    if (!region->expected_height_px) return 0;
    for (long i = 0; i < cells; ++i) {
        double value;
        if (!read_double(r, &value) || !(value > 0.0 && value <= VC_MAX_HEIGHT_PX)) return 0;
        region->expected_height_px[i] = (float)value;
    }
    return 1;
}

void vc_bundle_free(vc_bundle *bundle) {
    if (!bundle) return;
    for (int i = 0; i < bundle->region_count && bundle->regions; ++i) free(bundle->regions[i].expected_height_px);
    free(bundle->regions);
    memset(bundle, 0, sizeof *bundle);
}

static char *read_file(const char *path, size_t *size) {
    FILE *file = fopen(path, "rb");
    if (!file) return NULL;
    char *text = NULL;
    long length = -1;
    if (fseek(file, 0, SEEK_END) == 0) length = ftell(file);
    if (length >= 0 && length <= MAX_FILE_BYTES && fseek(file, 0, SEEK_SET) == 0) {
        text = malloc((size_t)length + 1);
        if (text && fread(text, 1, (size_t)length, file) != (size_t)length) {
            free(text);
            text = NULL;
        }
    }
    fclose(file);
    if (text) *size = (size_t)length;
    return text;
}

int vc_bundle_read(const char *path, vc_bundle *bundle, int *line) {
    if (line) *line = 0;
    if (!path || !bundle) return VC_ERROR_ARGUMENT;
    memset(bundle, 0, sizeof *bundle);
    reader r = {NULL, 0, 0, 1, {0}};
    r.text = read_file(path, &r.size);
    if (!r.text) return VC_ERROR_FILE;
    double offsets[VC_KEYPOINTS], lower_ankle;
    int channels, count, ok = keyword(&r, "visual-compiler-decoder") && read_int(&r, 1, 1000, &bundle->version) &&
                              bundle->version == VC_DECODER_VERSION &&
                              field_ints(&r, "frame_size", 2, 1, 1000000, bundle->frame_size) &&
                              field_ints(&r, "channels", 1, 1, 1000, &channels) && keyword(&r, "prior_offsets");
    for (int k = 0; ok && k < VC_KEYPOINTS; ++k) ok = read_double(&r, &offsets[k]);
    ok = ok && field_double(&r, "prior_lower_ankle", &lower_ankle) && field_ints(&r, "regions", 1, 1, 1000, &count);
    if (ok) {
        bundle->regions = calloc((size_t)count, sizeof(vc_region));
        ok = bundle->regions != NULL;
    }
    for (int i = 0; ok && i < count; ++i) {
        bundle->region_count = i + 1; /* what vc_bundle_free releases, if this region fails */
        ok = read_region(&r, offsets, lower_ankle, &bundle->regions[i]);
        if (ok) bundle->regions[i].channels = channels;
    }
    ok = ok && keyword(&r, "end") && !next_token(&r);
    free(r.text);
    if (!ok) {
        if (line) *line = r.line;
        vc_bundle_free(bundle);
        return VC_ERROR_FORMAT;
    }
    return VC_OK;
}
