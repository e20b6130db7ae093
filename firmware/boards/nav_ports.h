/*
 * nav_ports.h — the rover's and the base's navigation peers: the VN200 on
 * HAL_PORT_INS (F2's vn200 parser -> ins frames) and the Piksi on HAL_PORT_RTK
 * (F2's SBP parser -> rtk_* / gps_time frames, rtk_status at 1 Hz).
 *
 * The rover forwards every solution as it arrives (NAV_FORWARD_ALL); the base,
 * whose Piksi runs in base mode, keeps the latest position and GPS time and sends
 * them with its 1 Hz status (NAV_STATUS_ONLY). Every frame is stamped with the
 * board clock when the peer's packet was parsed (its last byte in); for ins frames
 * the board declares how long after the sample instant that is
 * (NAV_INS_STAMP_LATENCY_US).
 */
#ifndef AW_NAV_PORTS_H
#define AW_NAV_PORTS_H

#include <stdbool.h>
#include <stdint.h>

#include "board_link.h"
#include "hal.h"
#include "rover/sbp.h"
#include "rover/vn200.h"

#define NAV_STATUS_PERIOD_US 1000000u
/* The VN200's serial port as configured (its Binary Output 1 goes out at this rate;
 * board_pins.h wires HAL_PORT_INS at the same baud on the rover and the base). */
#define NAV_INS_BAUD 921600u
/* An ins frame is stamped when its packet's last byte has been parsed: the VN200's
 * output latency plus the packet's time on the line (8N1: 10 bit times per byte)
 * after the sample instant it describes. Declared to the host (stamp_latency). */
#define NAV_INS_STAMP_LATENCY_US \
    (VN200_OUTPUT_LATENCY_US + \
     (VN200_PACKET_BYTES * 10u * 1000000u + NAV_INS_BAUD / 2u) / NAV_INS_BAUD)

typedef enum { NAV_FORWARD_ALL = 0, NAV_STATUS_ONLY = 1 } nav_policy_t;

typedef struct {
    board_link_t *link;
    const hal_t *hal;
    nav_policy_t policy;
    vn200_parser_t vn;
    sbp_parser_t sbp;
    uint64_t now_us;           /* board time of the bytes being parsed */
    uint64_t last_sbp_us;
    bool have_sbp;
    aw_rtk_pos_t pos;          /* latest MSG_POS_LLH */
    bool have_pos;
    aw_gps_time_t gps_time;    /* latest MSG_GPS_TIME */
    bool have_gps_time;
    uint64_t next_status_us;
    uint32_t ins_frames;
} nav_ports_t;

void nav_ports_init(nav_ports_t *n, const hal_t *hal, board_link_t *link, nav_policy_t policy);
/* Reads both ports, parses, sends what is due; returns the next deadline. */
uint64_t nav_ports_poll(nav_ports_t *n);

#endif /* AW_NAV_PORTS_H */
