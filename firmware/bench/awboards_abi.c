/* ABI helpers compiled only into build/native/libawboards.so: struct sizes and field
 * offsets, so the Python ctypes mirrors (tests/firmware_algos/awboards.py) fail loudly
 * instead of reading garbage when a header changes. */
#include <stddef.h>
#include <string.h>

#include "base/pwm_capture.h"
#include "base/sbus.h"
#include "losa/frame.h"
#include "marker/marker_logic.h"
#include "quat.h"
#include "rover/rotor_speed.h"
#include "rover/sbp.h"
#include "rover/vn200.h"

#define ENTRY(t) {#t, sizeof(t)}

static const struct {
    const char *name;
    size_t size;
} sizes[] = {
    ENTRY(quat_t),
    ENTRY(losa_peak_cfg_t),
    ENTRY(losa_peak_t),
    ENTRY(losa_slot_cfg_t),
    ENTRY(losa_slot_state_t),
    ENTRY(losa_exposure_cfg_t),
    ENTRY(losa_exposure_state_t),
    ENTRY(losa_frame_cfg_t),
    ENTRY(losa_frame_state_t),
    ENTRY(losa_sensor_result_t),
    ENTRY(marker_att_cfg_t),
    ENTRY(marker_att_t),
    ENTRY(marker_cfg_t),
    ENTRY(marker_state_t),
    ENTRY(marker_output_t),
    ENTRY(vn200_ins_t),
    ENTRY(vn200_parser_t),
    ENTRY(sbp_msg_t),
    ENTRY(sbp_parser_t),
    ENTRY(rotor_speed_cfg_t),
    ENTRY(rotor_speed_t),
    ENTRY(rotor_speed_out_t),
    ENTRY(pwm_capture_cfg_t),
    ENTRY(pwm_channel_t),
    ENTRY(pwm_channel_out_t),
    ENTRY(sbus_frame_t),
    ENTRY(sbus_parser_t),
};

/* sizeof the named struct type, 0 if unknown. */
size_t awb_sizeof(const char *name)
{
    for (size_t i = 0; i < sizeof sizes / sizeof sizes[0]; i++) {
        if (strcmp(sizes[i].name, name) == 0) {
            return sizes[i].size;
        }
    }
    return 0;
}
