/* Decoder benchmark: `bench_proto CAPTURE [REPS]` decodes a capture file REPS times and
 * prints {"frames": N, "bytes": B, "ns_per_frame": best}. airwake bench also runs it
 * under callgrind with --toggle-collect=bench_decode for instructions per frame. */
#include <stdio.h>
#include <stdlib.h>
#include <time.h>

#include "aw_frame.h"

static void count_frame(void *ctx, const aw_frame_t *f)
{
    *(size_t *)ctx += f->payload_len != 0;
}

/* The measured work: one decoder over the whole capture, buffer form with a callback. */
__attribute__((noinline)) size_t bench_decode(const uint8_t *data, size_t len)
{
    size_t frames = 0;
    aw_decoder_t d;
    aw_decoder_init(&d, count_frame, &frames);
    aw_decoder_feed(&d, data, len);
    return frames;
}

static double now_ns(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec * 1e9 + (double)ts.tv_nsec;
}

int main(int argc, char **argv)
{
    if (argc < 2) {
        fprintf(stderr, "usage: %s CAPTURE [REPS]\n", argv[0]);
        return 2;
    }
    FILE *f = fopen(argv[1], "rb");
    if (f == NULL) {
        perror(argv[1]);
        return 2;
    }
    fseek(f, 0, SEEK_END);
    const long size = ftell(f);
    fseek(f, 0, SEEK_SET);
    uint8_t *data = malloc(size > 0 ? (size_t)size : 1u);
    if (data == NULL || fread(data, 1, (size_t)size, f) != (size_t)size) {
        fprintf(stderr, "%s: read failed\n", argv[1]);
        return 2;
    }
    fclose(f);
    const int reps = argc > 2 ? atoi(argv[2]) : 5;
    double best = 1e300;
    size_t frames = 0;
    for (int i = 0; i < reps; ++i) {
        const double t0 = now_ns();
        frames = bench_decode(data, (size_t)size);
        const double dt = now_ns() - t0;
        best = dt < best ? dt : best;
    }
    printf("{\"frames\": %zu, \"bytes\": %ld, \"ns_per_frame\": %.2f}\n", frames, size,
           frames ? best / (double)frames : 0.0);
    free(data);
    return 0;
}
