/* SBUS (Futaba serial RC, 100000 baud 8E2, inverted) frame decoder: optional pilot-
 * input source for the base instead of five PWM lines.
 *
 * Frame (25 bytes): 0x0F | 16 channels x 11 bits, LSB first, packed in 22 bytes |
 * flags (bit 0 ch17, bit 1 ch18, bit 2 frame lost, bit 3 failsafe) | 0x00 footer
 * (0x04/0x14/0x24/0x34 for SBUS2). Pulse width us = raw * 5 / 8 + 875
 * (raw 172..1811 -> 982..2006 us).
 * The stream parser resyncs by rescanning after a frame whose footer is wrong; call
 * sbus_parser_gap() when the UART reports an idle gap (frames are separated by one).
 */
#ifndef AW_SBUS_H
#define AW_SBUS_H

#include <stddef.h>
#include <stdint.h>

#define SBUS_FRAME_LEN 25u
#define SBUS_CHANNELS 16
#define SBUS_HEADER 0x0Fu
#define SBUS_FLAG_FRAME_LOST 0x04u
#define SBUS_FLAG_FAILSAFE 0x08u

typedef struct {
    uint16_t raw[SBUS_CHANNELS];
    uint16_t width_us[SBUS_CHANNELS];
    uint8_t flags;
} sbus_frame_t;

typedef struct {
    size_t n;
    uint32_t frames;
    uint32_t bad_frames;
    uint32_t bytes_dropped;
    uint8_t buf[SBUS_FRAME_LEN];
} sbus_parser_t;

/* Decode one complete frame; returns 0 when header or footer is wrong. */
int sbus_decode(const uint8_t frame[SBUS_FRAME_LEN], sbus_frame_t *out);

void sbus_parser_init(sbus_parser_t *p);
/* Returns 1 and fills *out when this byte completes a valid frame. */
int sbus_parser_feed(sbus_parser_t *p, uint8_t byte, sbus_frame_t *out);
void sbus_parser_gap(sbus_parser_t *p);

#endif
