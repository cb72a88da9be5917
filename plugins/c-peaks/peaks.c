/* c-peaks: a keylo detector plugin in plain C.
 *
 * Grid-bucketed intensity peaks: the image is cut into cells of `cell` x `cell` pixels and each
 * cell keeps its brightest pixel when it is a strict 3x3 local maximum at least `threshold`
 * above the mean of its 3x3 neighbourhood. Cheap, evenly spread keypoints on signal or
 * near-IR images.
 *
 * Build:  cc -shared -fPIC -O2 -I crates/keylo-plugin/include plugins/c-peaks/peaks.c \
 *            -o libc-peaks.so
 * Use:    [detector] kind = "plugin:c-peaks"  cell = 16  threshold = 8.0
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "keylo_plugin.h"

typedef struct {
    int cell;
    float threshold;
    KeyloKeypoint *keypoints; /* output buffer, owned by the instance */
    size_t capacity;
} Peaks;

static void fail(KeyloError *err, int32_t code, const char *message) {
    if (err) {
        err->code = code;
        snprintf(err->message, KEYLO_ERROR_MESSAGE_LEN, "%s", message);
    }
}

static void *peaks_create(KeyloError *err) {
    Peaks *p = calloc(1, sizeof *p);
    if (!p) {
        fail(err, KEYLO_ERR_INTERNAL, "out of memory");
        return NULL;
    }
    p->cell = 16;
    p->threshold = 8.0f;
    return p;
}

/* The configuration is the stage's TOML table as text, one `key = value` per line. */
static int32_t peaks_configure(void *state, const char *toml, KeyloError *err) {
    Peaks *p = state;
    char line[256];
    while (toml && *toml) {
        size_t n = strcspn(toml, "\n");
        if (n >= sizeof line) n = sizeof line - 1;
        memcpy(line, toml, n);
        line[n] = 0;
        toml += n + (toml[n] == '\n');
        char key[64];
        double value;
        if (line[0] == 0 || line[0] == '#') continue;
        if (sscanf(line, " %63[a-z_] = %lf", key, &value) != 2) {
            char msg[320];
            snprintf(msg, sizeof msg, "cannot read `%s`: expected `cell = N` or `threshold = X`", line);
            fail(err, KEYLO_ERR_CONFIG, msg);
            return KEYLO_ERR_CONFIG;
        }
        if (strcmp(key, "cell") == 0 && value >= 3 && value <= 1024) {
            p->cell = (int)value;
        } else if (strcmp(key, "threshold") == 0 && value >= 0) {
            p->threshold = (float)value;
        } else {
            char msg[320];
            snprintf(msg, sizeof msg, "`%s = %g`: unknown key or out of range (cell: 3..1024, threshold >= 0)", key, value);
            fail(err, KEYLO_ERR_CONFIG, msg);
            return KEYLO_ERR_CONFIG;
        }
    }
    return KEYLO_OK;
}

static void peaks_destroy(void *state) {
    Peaks *p = state;
    if (p) free(p->keypoints);
    free(p);
}

static int32_t peaks_detect(void *state, const KeyloImage *img, KeyloKeypoints *out, KeyloError *err) {
    Peaks *p = state;
    if (img->pixel_type != KEYLO_PIXEL_U8) {
        fail(err, KEYLO_ERR_INPUT, "only 8-bit images are supported");
        return KEYLO_ERR_INPUT;
    }
    size_t cells = (size_t)((img->width + p->cell - 1) / p->cell) * ((img->height + p->cell - 1) / p->cell);
    if (cells > p->capacity) {
        KeyloKeypoint *grown = realloc(p->keypoints, cells * sizeof *grown);
        if (!grown) {
            fail(err, KEYLO_ERR_INTERNAL, "out of memory");
            return KEYLO_ERR_INTERNAL;
        }
        p->keypoints = grown;
        p->capacity = cells;
    }
    size_t n = 0;
    const uint32_t cs = img->channels;
#define PX(x, y) ((float)img->data[(size_t)(y) * img->stride + (size_t)(x) * cs])
    for (uint32_t cy = 0; cy < img->height; cy += p->cell) {
        for (uint32_t cx = 0; cx < img->width; cx += p->cell) {
            float best = -1.0f;
            uint32_t bx = 0, by = 0;
            for (uint32_t y = cy > 0 ? cy : 1; y < cy + p->cell && y + 1 < img->height; y++) {
                for (uint32_t x = cx > 0 ? cx : 1; x < cx + p->cell && x + 1 < img->width; x++) {
                    float v = PX(x, y), sum = 0.0f;
                    int peak = 1;
                    for (int dy = -1; dy <= 1 && peak; dy++)
                        for (int dx = -1; dx <= 1; dx++) {
                            if (!dx && !dy) continue;
                            float u = PX(x + dx, y + dy);
                            sum += u;
                            if (u >= v) { peak = 0; break; }
                        }
                    float contrast = v - sum / 8.0f;
                    if (peak && contrast >= p->threshold && contrast > best) {
                        best = contrast;
                        bx = x;
                        by = y;
                    }
                }
            }
            if (best >= 0.0f) {
                KeyloKeypoint k = {(float)bx, (float)by, 7.0f, -1.0f, best, 0, 0};
                p->keypoints[n++] = k;
            }
        }
    }
#undef PX
    out->data = p->keypoints;
    out->len = n;
    return KEYLO_OK;
}

static const KeyloPluginKind KINDS[] = {{
    .stage = KEYLO_STAGE_DETECTOR,
    .summary = "grid-bucketed 3x3 intensity peaks (C example plugin)",
    .create = peaks_create,
    .configure = peaks_configure,
    .destroy = peaks_destroy,
    .detect = peaks_detect,
}};

static const KeyloPluginInfo INFO = {
    .abi_version = KEYLO_PLUGIN_ABI_VERSION,
    .name = "c-peaks",
    .version = "0.1.0",
    .kinds = KINDS,
    .kind_count = 1,
};

const KeyloPluginInfo *keylo_plugin_entry(void) { return &INFO; }
