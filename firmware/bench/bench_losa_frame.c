/* Callgrind driver: LOSA frames (4 sensors: peaks + slot tracking + exposure).
 * Usage: bench_losa_frame [frames]. 16 precomputed frames of noisy peaks (one sensor
 * moving across a slot boundary, one saturated, one weak) are processed in turn;
 * bench.py counts instructions inside losa_frame_process. */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>

#include "losa/frame.h"

#define FRAMES 16

static uint16_t lines[FRAMES][LOSA_SENSORS][LOSA_PIXELS];

static uint32_t lcg(uint32_t *s)
{
    *s = *s * 1664525u + 1013904223u;
    return *s >> 8;
}

static void make_line(uint16_t *px, double centre, double amp, uint32_t *seed)
{
    for (int k = 0; k < LOSA_PIXELS; k++) {
        const double u = k - centre;
        double v = 40.0 + amp * exp(-0.5 * u * u / 0.9) + (double)(lcg(seed) % 7u) - 3.0;
        v = v < 0.0 ? 0.0 : (v > 1023.0 ? 1023.0 : v);
        px[k] = (uint16_t)v;
    }
}

int main(int argc, char **argv)
{
    const long n = argc > 1 ? atol(argv[1]) : 1000;
    uint32_t seed = 12345u;
    for (int f = 0; f < FRAMES; f++) {
        make_line(lines[f][0], 20.0 + 0.37 * f, 500.0, &seed);
        make_line(lines[f][1], fmod(120.0 + 0.9 * f, 128.0), 400.0, &seed); /* crosses the end */
        make_line(lines[f][2], 64.3 + 0.1 * f, 2500.0, &seed);             /* saturated */
        make_line(lines[f][3], 90.0 - 0.2 * f, 120.0, &seed);              /* weak */
    }
    const losa_frame_cfg_t cfg = losa_frame_default_cfg(10);
    static losa_frame_state_t st;
    losa_frame_init(&st, &cfg, 500);
    losa_sensor_result_t out[LOSA_SENSORS];
    double sum = 0.0;
    for (long i = 0; i < n; i++) {
        losa_frame_process(&st, &cfg, (const uint16_t(*)[LOSA_PIXELS])lines[i % FRAMES], out);
        sum += out[0].pos_px + out[1].pos_px + out[2].pos_px + out[3].pos_px;
    }
    printf("frames %ld checksum %.3f\n", n, sum);
    return 0;
}
