/* Slot tracking across the three optical slots of a LOSA module (reference §3.3.1.5).
 *
 * The slots are one sensor length apart, so the same LED lights the array through at
 * most one slot at a time and an image leaving one end re-enters at the other as the
 * marker moves. Positions are unwrapped with a period of 128 px:
 *     unwrapped_px = raw_px + 128 * (slot - 1),   slot 0, 1 (central), 2
 * i.e. slot k covers unwrapped [128 (k - 1) - 0.5, 128 k - 0.5). At start, and after
 * a long loss, the peak is assumed to come through the central slot (as the reference
 * does). A jump of more than `jump_px` between consecutive valid peaks is a change of
 * slot in the direction that keeps the unwrapped motion shortest.
 */
#ifndef AW_LOSA_SLOTS_H
#define AW_LOSA_SLOTS_H

#include <stdint.h>

#include "peak.h"

#define LOSA_SLOTS 3
#define LOSA_SLOT_CENTRAL 1

/* Flags added to a sensor result (above the LOSA_PEAK_* bits). */
#define LOSA_SLOT_CHANGED 0x10u      /* the slot changed on this frame */
#define LOSA_SLOT_OUT_OF_RANGE 0x20u /* a jump asked for a slot beyond the outer ones */
#define LOSA_SLOT_RESET 0x40u        /* lost for too long: back to the central slot */

typedef struct {
    float jump_px;             /* a raw jump larger than this changes slot (64) */
    uint16_t lost_reset_frames; /* invalid frames before the slot resets to central */
} losa_slot_cfg_t;

typedef struct {
    float last_raw_px;
    uint16_t lost_frames;
    uint8_t slot;
    uint8_t have_last;
    uint32_t slot_changes; /* counters for the heartbeat */
    uint32_t resets;
} losa_slot_state_t;

losa_slot_cfg_t losa_slot_default_cfg(void);
void losa_slot_init(losa_slot_state_t *st);

/* Feed one frame's peak of this sensor. Returns LOSA_SLOT_* flags; *slot and
 * *unwrapped_px are the tracked slot and position (the last known ones when the peak
 * is not valid). */
uint8_t losa_slot_update(losa_slot_state_t *st, const losa_slot_cfg_t *cfg, const losa_peak_t *pk,
                         uint8_t *slot, float *unwrapped_px);

#endif
