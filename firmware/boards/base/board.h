/*
 * board.h (base) — the ship's board (reference §4.2.2): five RC receiver PWM
 * channels (input capture -> F2's pwm_capture -> pilot_inputs at 50 Hz), its own
 * VN200 and Piksi status (nav_ports, status policy), and the rover's frames from
 * the XBee (HAL_PORT_ROVER) forwarded to the host port byte for byte.
 *
 * Forwarding cuts the rover's stream at the 0x00 frame delimiters and queues each
 * segment whole, so the base's own frames never land inside a rover frame. The
 * bytes are not decoded or changed: a frame keeps the rover's origin id, sequence
 * number and CRC, and corruption on the radio link reaches the host's decoder
 * (which counts it) instead of being hidden here.
 *
 * Pilot inputs go out once per RC frame, when the frame is complete (every valid
 * channel has a new pulse, or the first new pulse is 3/4 of a frame period old: a
 * channel missed its pulse), stamped with the frame's first rising edge: the instant
 * the frame's commands describe, whatever the receiver's channel layout and however
 * its frame rate beats against the board's clock. While no frame comes, a keep-alive
 * (valid bits cleared as the channels time out) goes out at BASE_PILOT_HZ.
 *
 * The other way, every byte the host sends the base is also passed to the rover
 * unchanged, so the rover answers the host's time-sync requests (each reply carries
 * its origin board) and the host can map the rover's clock too.
 */
#ifndef AW_BOARD_BASE_H
#define AW_BOARD_BASE_H

#include <stdint.h>

#include "board_link.h"
#include "hal.h"
#include "nav_ports.h"
#include "pwm_capture.h"

#define BOARD_NAME "base"
#define BOARD_ID AW_BOARD_BASE

#define BASE_RC_CHANNELS 5
#define BASE_PILOT_HZ 50u /* keep-alive rate while no RC frame completes */
/* Gathering a frame's pulses ends 3/4 of a frame period after its first rising edge
 * (before two pulses give a period: 3/4 of a 50 Hz frame). */
#define BASE_RC_GATHER_DEFAULT_US 15000u
/* The RC link's latency from the pilot's stick to the frame's first pulse is not known
 * for our receiver; the pulses are what the servos get, so the frame's start is the
 * instant its commands describe. Declared to the host (stamp_latency). */
#define BASE_RC_STAMP_LATENCY_US 0u
#define BASE_WATCHDOG_MS 500u

typedef struct {
    uint8_t seg[1u + AW_MAX_ENCODED_SIZE + 1u]; /* 0x00, the segment, 0x00 */
    size_t len;                                 /* bytes in seg, leading 0x00 included */
    uint32_t segments;                          /* segments forwarded */
    uint32_t bytes;                             /* rover bytes forwarded */
    uint32_t dropped_bytes;                     /* refused by the host port (ring full) */
} forwarder_t;

typedef struct {
    board_link_t link;
    nav_ports_t nav;
    pwm_capture_cfg_t rc_cfg;
    pwm_channel_t rc[BASE_RC_CHANNELS];
    forwarder_t fwd;
    uint32_t relay_dropped_bytes; /* host -> rover bytes the rover port refused */
    uint32_t sent_pulses[BASE_RC_CHANNELS]; /* each channel's pulse count at the last frame */
    uint64_t last_frame_us;                  /* when the last RC frame went out */
    uint64_t t0_us;
    uint32_t pilot_k;
} base_board_t;

extern base_board_t base_board; /* for tests */

void board_init(const hal_t *hal);
uint64_t board_task(const hal_t *hal);

#endif /* AW_BOARD_BASE_H */
