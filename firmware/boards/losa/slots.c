/* Slot tracking, see slots.h. */
#include "slots.h"

losa_slot_cfg_t losa_slot_default_cfg(void)
{
    /* 64 px = half the array: legitimate motion is a few px per 300 Hz frame. 90
     * frames = 0.3 s lost before the slot is forgotten. */
    const losa_slot_cfg_t cfg = {.jump_px = 64.0f, .lost_reset_frames = 90};
    return cfg;
}

void losa_slot_init(losa_slot_state_t *st)
{
    st->last_raw_px = 0.0f;
    st->lost_frames = 0;
    st->slot = LOSA_SLOT_CENTRAL;
    st->have_last = 0;
    st->slot_changes = 0;
    st->resets = 0;
}

uint8_t losa_slot_update(losa_slot_state_t *st, const losa_slot_cfg_t *cfg, const losa_peak_t *pk,
                         uint8_t *slot, float *unwrapped_px)
{
    uint8_t flags = 0;
    if (!(pk->flags & LOSA_PEAK_VALID)) {
        if (st->lost_frames < UINT16_MAX) {
            st->lost_frames++;
        }
        if (st->have_last && st->lost_frames > cfg->lost_reset_frames) {
            st->have_last = 0;
            if (st->slot != LOSA_SLOT_CENTRAL) {
                st->slot = LOSA_SLOT_CENTRAL;
                st->resets++;
                flags |= LOSA_SLOT_RESET;
            }
        }
    } else {
        if (st->have_last) {
            const float jump = pk->pos_px - st->last_raw_px;
            int step = 0;
            if (jump < -cfg->jump_px) {
                step = 1; /* left the high end, re-entered at the low end */
            } else if (jump > cfg->jump_px) {
                step = -1;
            }
            const int next = (int)st->slot + step;
            if (next < 0 || next >= LOSA_SLOTS) {
                flags |= LOSA_SLOT_OUT_OF_RANGE;
            } else if (step != 0) {
                st->slot = (uint8_t)next;
                st->slot_changes++;
                flags |= LOSA_SLOT_CHANGED;
            }
        }
        st->last_raw_px = pk->pos_px;
        st->have_last = 1;
        st->lost_frames = 0;
    }
    *slot = st->slot;
    *unwrapped_px = st->last_raw_px + (float)LOSA_PIXELS * (float)((int)st->slot - LOSA_SLOT_CENTRAL);
    return flags;
}
