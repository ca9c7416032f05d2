/* Visual Compiler's decoder in C99 (libm only): a region's heat maps -> people, the algorithm of
 * src/vc/deploy/decode.py (its module docstring numbers the steps; this file follows them and names them), and the
 * bundle's flat decoder file (decoder.txt, written by vc-export beside manifest.json), which gives each region's
 * crop window, network input, decoder settings and expected person heights without a JSON parser.
 *
 * The numpy decoder is the reference: on the same float32 heat maps this one reports the same people (count
 * equal, boxes and keypoints within 1e-3 px, scores equal), which tests/test_native_decode.py checks on random,
 * degenerate and hostile maps under AddressSanitizer and UndefinedBehaviorSanitizer, and on real frames. Heat maps
 * holding NaN or infinite values, and expected heights outside (0, VC_MAX_HEIGHT_PX], are refused by both.
 *
 * Thread safety: every call allocates its own scratch memory; nothing is global.
 */
#ifndef VC_DECODE_H
#define VC_DECODE_H

#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

#define VC_DECODER_VERSION 1
#define VC_KEYPOINTS 17
#define VC_PAIRS 8
/* The heat-map layouts decoded, by channel count: handedness maps; + centre offsets; + the fine centre map; */
#define VC_LAYOUT_HANDEDNESS 27
#define VC_LAYOUT_OFFSETS 29
#define VC_LAYOUT_FINE 33
/* ... + the head and size maps (decode.py's step 5 reads people from the heads too). */
#define VC_LAYOUT_HEAD 35
/* The retired layout (keypoint pairs in anatomical order, no handedness): refused by name. */
#define VC_LAYOUT_ANATOMICAL 19
/* The tallest expected person height accepted, in network-input pixels. */
#define VC_MAX_HEIGHT_PX 100000.0

/* Results of vc_decode and vc_bundle_read. */
enum vc_status {
    VC_OK = 0,
    VC_ERROR_ARGUMENT = 1,    /* a null pointer, a negative size, a capacity below the settings' max_people */
    VC_ERROR_ANATOMICAL = 2,  /* heat maps in the retired 19-map layout */
    VC_ERROR_LAYOUT = 3,      /* a channel count that is none of the layouts */
    VC_ERROR_NOT_FINITE = 4,  /* a heat-map value is NaN or infinite */
    VC_ERROR_HEIGHTS = 5,     /* an expected height is not finite or outside (0, VC_MAX_HEIGHT_PX] */
    VC_ERROR_MEMORY = 6,      /* scratch memory could not be allocated (or its size overflows) */
    VC_ERROR_FILE = 7,        /* the bundle's decoder file cannot be read */
    VC_ERROR_FORMAT = 8       /* the bundle's decoder file is malformed or of another version */
};

/* decode.py's DecodeConfig and UprightPrior together. */
typedef struct {
    int stride;
    double centre_threshold;
    double keypoint_threshold;
    double mask_threshold;
    double search_sigma;
    double default_height_px;
    int max_people;
    double min_centre_separation;
    double reach_sideways;
    double reach_vertical;
    double min_width;
    double side_margin;
    double keypoint_height_range;
    double keypoint_peak_floor;
    double vote_support;
    double vote_separation;  /* NaN: min_centre_separation */
    double prior_offsets[VC_KEYPOINTS];
    double prior_lower_ankle;
} vc_decode_config;

/* decode.py's DecodedPerson; coordinates in network-input pixels (pixel centres at integers). */
typedef struct {
    double score;
    double centre[2];
    double keypoints[VC_KEYPOINTS][3];  /* x, y, confidence; anatomical (COCO) order */
    double box[4];                      /* x0, y0, x1, y1: outer edges */
    float pair_handedness[VC_PAIRS];
    int weak;
    int head_found; /* read from the head map (step 5) */
} vc_person;

/* People in one sample's heat maps (channels, height, width; C order, float32).
 * expected_height_px: (height, width) per cell, or NULL for the settings' default height.
 * weak_above: decode the centre peaks down to it as weak people (for a tracker); NaN: none.
 * people: room for at least config->max_people (twice that for heat maps with the head map); *count receives how
 * many were decoded. From a network with a head map (VC_LAYOUT_HEAD), the people of the centre map come first,
 * then every strong person read from the heads (head_found; decode.py's step 5 and decode_readings): which of those
 * to add depends on which of the first the caller keeps (decode.py's with_heads_added, then one_head_each).
 * strong_owner, weak_owner, head_owner: (height, width) each, or NULL: the person owning each cell of the mask
 * (-1: none), among the strong people of the centre map, the weak ones, and those read from the heads (step 5);
 * a cell can belong to one of each. */
int vc_decode(const float *heatmaps, int channels, int height, int width, const vc_decode_config *config,
              const float *expected_height_px, double weak_above, vc_person *people, int capacity, int *count,
              int32_t *strong_owner, int32_t *weak_owner, int32_t *head_owner);

/* A short English sentence for a status. */
const char *vc_status_message(int status);

/* One region of the bundle's decoder file. */
typedef struct {
    char name[64];
    int crop_window[4];  /* x0, y0, width, height in frame pixels */
    int input_size[2];   /* network input width, height */
    int channels;        /* heat maps the network emits */
    int heatmap_size[2]; /* heat-map width, height (cells) */
    vc_decode_config config;
    float *expected_height_px; /* heatmap_size[1] x heatmap_size[0] */
} vc_region;

typedef struct {
    int version;
    int frame_size[2];
    int region_count;
    vc_region *regions;
} vc_bundle;

/* Reads a bundle's decoder file (decoder.txt). On failure the bundle is left empty and, where given, line
 * receives the line at fault (0: the file as a whole). */
int vc_bundle_read(const char *path, vc_bundle *bundle, int *line);
void vc_bundle_free(vc_bundle *bundle);

#ifdef __cplusplus
}
#endif

#endif
