/* One region of a Visual Compiler bundle, in C: a frame in, the region's people out.
 *
 *     run_region BUNDLE/decoder.txt REGION BUNDLE/models/REGION.onnx FRAME.ppm
 *
 * The frame is a binary PPM (P6, 8-bit RGB) of the bundle's camera. The region's crop window (from decoder.txt,
 * read by vc_bundle_read) is cut out as uint8 NHWC RGB, the network (OpenVINO's C API, CPU plugin) resizes and
 * normalises it itself, and vc_decode turns its heat maps into people. They are printed one a line, in frame
 * pixels: score, box x0 y0 x1 y1, then x y confidence of the 17 COCO keypoints, "weak" for a weak one.
 *
 * Why OpenVINO: onnxruntime's pip wheel ships its library but not its C headers, OpenVINO's ships both
 * (openvino/include/openvino/c/openvino.h, openvino/libs/libopenvino_c.so). Build (tests/test_c_example.py does):
 *
 *     cc -std=c99 -O2 -ffp-contract=off -I src/vc/deploy/native -I $OV/include run_region.c \
 *        src/vc/deploy/native/vc_decode.c src/vc/deploy/native/vc_bundle.c -L $OV/libs -l:libopenvino_c.so.VERSION -lm
 *
 * where $OV is the openvino package's folder. Exit status 2 for bad input (one line on stderr saying what), 1 for
 * an engine failure.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <openvino/c/openvino.h>

#include "vc_decode.h"

static unsigned char *read_ppm(const char *path, int *width, int *height) {
    FILE *file = fopen(path, "rb");
    if (!file) return NULL;
    int maximum = 0;
    unsigned char *pixels = NULL;
    if (fscanf(file, "P6 %d %d %d", width, height, &maximum) == 3 && maximum == 255 && *width > 0 && *height > 0 &&
        fgetc(file) != EOF) {
        size_t size = (size_t)*width * (size_t)*height * 3;
        pixels = malloc(size);
        if (pixels && fread(pixels, 1, size, file) != size) {
            free(pixels);
            pixels = NULL;
        }
    }
    fclose(file);
    return pixels;
}

/* The region's heat maps from its network on the crop; 0 on success. */
static int run_network(const char *model_path, unsigned char *crop, int crop_width, int crop_height, float **maps,
                       int64_t dimensions[4]) {
    ov_core_t *core = NULL;
    ov_model_t *model = NULL;
    ov_compiled_model_t *compiled = NULL;
    ov_infer_request_t *request = NULL;
    ov_tensor_t *input = NULL, *output = NULL;
    ov_shape_t shape = {0, NULL}, output_shape = {0, NULL};
    int64_t input_dimensions[4] = {1, crop_height, crop_width, 3};
    void *data = NULL;
    int failed = ov_core_create(&core) || ov_core_read_model(core, model_path, NULL, &model) ||
                 /* f32, as the Python runtime asks (vc.deploy.engines): not a CPU's bf16 */
                 ov_core_compile_model(core, model, "CPU", 2, &compiled, ov_property_key_hint_inference_precision,
                                       "f32") ||
                 ov_compiled_model_create_infer_request(compiled, &request) ||
                 ov_shape_create(4, input_dimensions, &shape) ||
                 ov_tensor_create_from_host_ptr(U8, shape, crop, &input) ||
                 ov_infer_request_set_input_tensor_by_index(request, 0, input) || ov_infer_request_infer(request) ||
                 ov_infer_request_get_output_tensor_by_index(request, 0, &output) ||
                 ov_tensor_get_shape(output, &output_shape) || output_shape.rank != 4 || ov_tensor_data(output, &data);
    if (!failed) {
        size_t count = 1;
        for (int i = 0; i < 4; ++i) count *= (size_t)(dimensions[i] = output_shape.dims[i]);
        *maps = malloc(count * sizeof(float));
        if (*maps) memcpy(*maps, data, count * sizeof(float));
        failed = *maps == NULL;
    }
    if (output_shape.dims) ov_shape_free(&output_shape);
    if (shape.dims) ov_shape_free(&shape);
    if (output) ov_tensor_free(output);
    if (input) ov_tensor_free(input);
    if (request) ov_infer_request_free(request);
    if (compiled) ov_compiled_model_free(compiled);
    if (model) ov_model_free(model);
    if (core) ov_core_free(core);
    return failed;
}

int main(int argc, char **argv) {
    if (argc != 5) {
        fprintf(stderr, "usage: %s BUNDLE/decoder.txt REGION MODEL.onnx FRAME.ppm\n", argv[0]);
        return 2;
    }
    vc_bundle bundle;
    int line = 0, status = vc_bundle_read(argv[1], &bundle, &line);
    if (status != VC_OK) {
        fprintf(stderr, "error: %s, line %d: %s\n", argv[1], line, vc_status_message(status));
        return 2;
    }
    const vc_region *region = NULL;
    for (int i = 0; i < bundle.region_count; ++i)
        if (strcmp(bundle.regions[i].name, argv[2]) == 0) region = &bundle.regions[i];
    int width = 0, height = 0;
    unsigned char *frame = region ? read_ppm(argv[4], &width, &height) : NULL;
    if (!region || !frame || width != bundle.frame_size[0] || height != bundle.frame_size[1]) {
        fprintf(stderr, "error: %s\n", !region ? "no such region in the decoder file"
                                              : "the frame is not a binary PPM of the bundle's camera's size");
        free(frame);
        vc_bundle_free(&bundle);
        return 2;
    }
    const int *window = region->crop_window; /* x0, y0, width, height */
    unsigned char *crop = malloc((size_t)window[2] * (size_t)window[3] * 3);
    for (int row = 0; crop && row < window[3]; ++row)
        memcpy(crop + (size_t)row * window[2] * 3, frame + ((size_t)(window[1] + row) * width + window[0]) * 3,
               (size_t)window[2] * 3);
    float *maps = NULL;
    int64_t dimensions[4] = {0, 0, 0, 0};
    int result = 1;
    if (crop && run_network(argv[3], crop, window[2], window[3], &maps, dimensions) == 0 &&
        dimensions[2] == region->heatmap_size[1] && dimensions[3] == region->heatmap_size[0]) {
        /* room for the people of the centre map and, from a network with a head map, those read from the heads */
        vc_person *people = malloc(sizeof(vc_person) * (size_t)(2 * region->config.max_people + 1));
        int count = 0;
        status = people ? vc_decode(maps, (int)dimensions[1], (int)dimensions[2], (int)dimensions[3], &region->config,
                                    region->expected_height_px, NAN, people,
                                    2 * region->config.max_people + 1, &count, NULL, NULL, NULL)
                        : VC_ERROR_MEMORY;
        if (status == VC_OK) {
            /* network-input pixels -> frame pixels (pixel centres at integers in both) */
            double scale_x = (double)region->input_size[0] / window[2];
            double scale_y = (double)region->input_size[1] / window[3];
            for (int i = 0; i < count; ++i) {
                const vc_person *p = &people[i];
                printf("%.9g %.9g %.9g %.9g %.9g", p->score, window[0] + (p->box[0] + 0.5) / scale_x - 0.5,
                       window[1] + (p->box[1] + 0.5) / scale_y - 0.5, window[0] + (p->box[2] + 0.5) / scale_x - 0.5,
                       window[1] + (p->box[3] + 0.5) / scale_y - 0.5);
                for (int k = 0; k < VC_KEYPOINTS; ++k)
                    printf(" %.9g %.9g %.9g", window[0] + (p->keypoints[k][0] + 0.5) / scale_x - 0.5,
                           window[1] + (p->keypoints[k][1] + 0.5) / scale_y - 0.5, p->keypoints[k][2]);
                printf("%s\n", p->weak ? " weak" : "");
            }
            result = 0;
        } else {
            fprintf(stderr, "error: the decoder refused the heat maps: %s\n", vc_status_message(status));
        }
        free(people);
    } else {
        fprintf(stderr, "error: the network did not run on the crop (OpenVINO), or its heat maps are not the "
                        "region's size\n");
    }
    free(maps);
    free(crop);
    free(frame);
    vc_bundle_free(&bundle);
    return result;
}
