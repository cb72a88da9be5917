/* Embeds a keylo pipeline through the C API (include/keylo.h).
 *
 * usage: embed CONFIG.toml FRAMES_DIR N frame|points
 * Reads N frames FRAMES_DIR/frame_K.bin (u32 rows, u32 cols, f64 timestamp, f64 column_times[cols],
 * f32 xyz[3*rows*cols], f32 signal[rows*cols], u8 valid[rows*cols]), pushes each as an organised
 * frame or as an unorganised cloud with per-point times, and prints one line per frame:
 *   pose K tx ty tz qx qy qz qw CLOUD_POINTS
 *   degeneracy K WEAK CONDITION LAMBDA_MIN LAMBDA_MAX |FIRST_EIGENVECTOR| RESIDUALS   (or: degeneracy K none) */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "keylo.h"

static char *read_text(const char *path) {
    FILE *f = fopen(path, "rb");
    if (!f) return NULL;
    fseek(f, 0, SEEK_END);
    long n = ftell(f);
    fseek(f, 0, SEEK_SET);
    char *text = calloc((size_t)n + 1, 1);
    if (text && fread(text, 1, (size_t)n, f) != (size_t)n) { free(text); text = NULL; }
    fclose(f);
    return text;
}

#define READ(ptr, count) if (fread((ptr), sizeof *(ptr), (count), f) != (size_t)(count)) { fclose(f); return 1; }

typedef struct {
    uint32_t rows, cols;
    double timestamp;
    double *column_times;
    float *xyz, *signal;
    uint8_t *valid;
} Frame;

static int read_frame(const char *path, Frame *fr) {
    FILE *f = fopen(path, "rb");
    if (!f) return 1;
    READ(&fr->rows, 1);
    READ(&fr->cols, 1);
    READ(&fr->timestamp, 1);
    size_t n = (size_t)fr->rows * fr->cols;
    fr->column_times = malloc(fr->cols * sizeof(double));
    fr->xyz = malloc(3 * n * sizeof(float));
    fr->signal = malloc(n * sizeof(float));
    fr->valid = malloc(n);
    READ(fr->column_times, fr->cols);
    READ(fr->xyz, 3 * n);
    READ(fr->signal, n);
    READ(fr->valid, n);
    fclose(f);
    return 0;
}

static void free_frame(Frame *fr) {
    free(fr->column_times); free(fr->xyz); free(fr->signal); free(fr->valid);
}

static int push_points(KeyloPipeline *p, const Frame *fr) {
    size_t n = (size_t)fr->rows * fr->cols, m = 0;
    float *xyz = malloc(3 * n * sizeof(float)), *intensity = malloc(n * sizeof(float));
    double *times = malloc(n * sizeof(double));
    for (size_t i = 0; i < n; i++) {
        if (!fr->valid[i]) continue;
        memcpy(xyz + 3 * m, fr->xyz + 3 * i, 3 * sizeof(float));
        intensity[m] = fr->signal[i];
        times[m] = fr->column_times[i % fr->cols] - fr->timestamp;
        m++;
    }
    int rc = keylo_pipeline_push_points(p, fr->timestamp, xyz, times, intensity, m);
    free(xyz); free(intensity); free(times);
    return rc;
}

int main(int argc, char **argv) {
    if (argc != 5) { fprintf(stderr, "usage: embed CONFIG FRAMES_DIR N frame|points\n"); return 2; }
    char *toml = read_text(argv[1]);
    if (!toml) { fprintf(stderr, "cannot read %s\n", argv[1]); return 2; }
    char error[1024];
    KeyloPipeline *p = keylo_pipeline_new(toml, NULL, error, sizeof error);
    free(toml);
    if (!p) { fprintf(stderr, "keylo_pipeline_new: %s\n", error); return 1; }
    KeyloPose pose = {.size = sizeof pose};
    if (keylo_pipeline_pose(p, &pose) == KEYLO_CAPI_OK) { fprintf(stderr, "a pose before any frame\n"); return 1; }
    int frames = atoi(argv[3]), points = strcmp(argv[4], "points") == 0;
    printf("keylo %s\n", keylo_version());
    /* A global map of the frames, in FRAMES_DIR/map_MODE; bad settings are refused first. */
    char map_dir[4096];
    snprintf(map_dir, sizeof map_dir, "%s/map_%s", argv[2], argv[4]);
    if (keylo_pipeline_save_map(p, map_dir, "voxel_size = -1") != KEYLO_CAPI_ERROR) return 1;
    printf("map error %s\n", keylo_pipeline_error(p));
    if (keylo_pipeline_save_map(p, map_dir, "voxel_size = 0.1")) {
        fprintf(stderr, "save_map: %s\n", keylo_pipeline_error(p));
        return 1;
    }
    for (int k = 0; k < frames; k++) {
        char path[4096];
        Frame fr;
        snprintf(path, sizeof path, "%s/frame_%d.bin", argv[2], k);
        if (read_frame(path, &fr)) { fprintf(stderr, "cannot read %s\n", path); return 2; }
        int rc;
        if (points) {
            rc = push_points(p, &fr);
        } else {
            KeyloFrameIn in = {.size = sizeof in, .rows = fr.rows, .cols = fr.cols, .timestamp = fr.timestamp,
                               .column_times = fr.column_times, .xyz = fr.xyz, .signal = fr.signal, .valid = fr.valid};
            rc = keylo_pipeline_push_frame(p, &in);
        }
        free_frame(&fr);
        if (rc != KEYLO_CAPI_OK) { fprintf(stderr, "frame %d: %s\n", k, keylo_pipeline_error(p)); return 1; }
        const double *xyz;
        size_t n;
        if (keylo_pipeline_pose(p, &pose) || keylo_pipeline_cloud(p, &xyz, &n)) {
            fprintf(stderr, "frame %d: %s\n", k, keylo_pipeline_error(p));
            return 1;
        }
        for (size_t i = 0; i < 3 * n; i++)
            if (!isfinite(xyz[i])) { fprintf(stderr, "frame %d: non-finite cloud\n", k); return 1; }
        printf("pose %d %.6f %.6f %.6f %.6f %.6f %.6f %.6f %zu\n", k, pose.translation[0], pose.translation[1],
               pose.translation[2], pose.rotation[0], pose.rotation[1], pose.rotation[2], pose.rotation[3], n);
        KeyloDegeneracy d = {.size = sizeof d};
        int drc = keylo_pipeline_degeneracy(p, &d);
        if (drc == KEYLO_CAPI_NOT_ANALYSED) {
            printf("degeneracy %d none\n", k);
        } else if (drc == KEYLO_CAPI_OK) {
            double norm = 0.0;
            for (int j = 0; j < 6; j++) norm += d.eigenvectors[j] * d.eigenvectors[j];
            printf("degeneracy %d %u %.6g %.6g %.6g %.6f %llu\n", k, d.weak, d.condition, d.eigenvalues[0],
                   d.eigenvalues[5], sqrt(norm), (unsigned long long)d.residuals);
            /* The fitted covariance: symmetric, a positive diagonal. */
            double c[36];
            if (keylo_pipeline_fitted_covariance(p, c) != KEYLO_CAPI_OK) { fprintf(stderr, "frame %d: no fitted covariance\n", k); return 1; }
            for (int i = 0; i < 6; i++)
                for (int j = 0; j < 6; j++)
                    if (!(c[6 * i + i] > 0.0) || fabs(c[6 * i + j] - c[6 * j + i]) > 1e-12 * (fabs(c[6 * i + j]) + 1e-30)) {
                        fprintf(stderr, "frame %d: fitted covariance not symmetric with a positive diagonal\n", k);
                        return 1;
                    }
            printf("covariance %d %.6g %.6g\n", k, c[0], c[35]);
        } else {
            fprintf(stderr, "frame %d: %s\n", k, keylo_pipeline_error(p));
            return 1;
        }
    }
    if (keylo_pipeline_finish_map(p)) { fprintf(stderr, "finish_map: %s\n", keylo_pipeline_error(p)); return 1; }
    /* Bad input is an error, not a crash. */
    if (keylo_pipeline_push_points(p, 0.0, NULL, NULL, NULL, 0) != KEYLO_CAPI_ERROR) return 1;
    printf("error %s\n", keylo_pipeline_error(p));
    keylo_pipeline_free(p);
    return 0;
}
