/* nav_ports.c — see nav_ports.h. */
#include "nav_ports.h"

#include <string.h>

static void on_ins(void *ctx, const vn200_ins_t *v)
{
    nav_ports_t *n = ctx;
    aw_ins_t m = {
        .time_startup_ns = v->time_startup_ns,
        .lat_deg = v->lla[0],
        .lon_deg = v->lla[1],
        .alt_m = v->lla[2],
        .ins_status = v->ins_status,
    };
    memcpy(m.ypr_deg, v->ypr_deg, sizeof(m.ypr_deg));
    memcpy(m.angular_rate_frd_rad_s, v->angular_rate_rad_s, sizeof(m.angular_rate_frd_rad_s));
    memcpy(m.vel_ned_m_s, v->vel_ned_m_s, sizeof(m.vel_ned_m_s));
    memcpy(m.accel_frd_m_s2, v->accel_m_s2, sizeof(m.accel_frd_m_s2));
    (void)board_link_send(n->link, AW_ID_INS, &m, (uint32_t)n->now_us);
    n->ins_frames++;
}

static void on_sbp(void *ctx, const sbp_msg_t *s)
{
    nav_ports_t *n = ctx;
    n->last_sbp_us = n->now_us;
    n->have_sbp = true;
    if (!s->decoded) {
        return;
    }
    uint32_t t = (uint32_t)n->now_us;
    bool forward = n->policy == NAV_FORWARD_ALL;
    switch (s->msg_type) {
    case SBP_MSG_BASELINE_NED: {
        const sbp_baseline_ned_t *b = &s->m.baseline_ned;
        aw_rtk_baseline_t m = {
            .gps_tow_ms = b->tow,
            .baseline_ned_mm = {b->n, b->e, b->d},
            .h_accuracy_mm = b->h_accuracy,
            .v_accuracy_mm = b->v_accuracy,
            .num_sats = b->n_sats,
            .fix_mode = (uint8_t)(b->flags & 7u),
        };
        if (forward) {
            (void)board_link_send(n->link, AW_ID_RTK_BASELINE, &m, t);
        }
        return;
    }
    case SBP_MSG_POS_LLH: {
        const sbp_pos_llh_t *p = &s->m.pos_llh;
        aw_rtk_pos_t m = {
            .gps_tow_ms = p->tow,
            .lat_deg = p->lat,
            .lon_deg = p->lon,
            .height_m = p->height,
            .h_accuracy_mm = p->h_accuracy,
            .v_accuracy_mm = p->v_accuracy,
            .num_sats = p->n_sats,
            .fix_mode = (uint8_t)(p->flags & 7u),
        };
        n->pos = m;
        n->have_pos = true;
        if (forward) {
            (void)board_link_send(n->link, AW_ID_RTK_POS, &m, t);
        }
        return;
    }
    case SBP_MSG_VEL_NED: {
        const sbp_vel_ned_t *v = &s->m.vel_ned;
        aw_rtk_vel_t m = {
            .gps_tow_ms = v->tow,
            .vel_ned_mm_s = {v->n, v->e, v->d},
            .h_accuracy_mm_s = v->h_accuracy,
            .v_accuracy_mm_s = v->v_accuracy,
            .num_sats = v->n_sats,
            .fix_mode = (uint8_t)(v->flags & 7u),
        };
        if (forward) {
            (void)board_link_send(n->link, AW_ID_RTK_VEL, &m, t);
        }
        return;
    }
    case SBP_MSG_GPS_TIME: {
        const sbp_gps_time_t *g = &s->m.gps_time;
        aw_gps_time_t m = {
            .gps_week = g->wn,
            .gps_tow_ms = g->tow,
            .ns_residual_ns = g->ns_residual,
            .time_source = (uint8_t)(g->flags & 7u),
        };
        n->gps_time = m;
        n->have_gps_time = true;
        if (forward) {
            (void)board_link_send(n->link, AW_ID_GPS_TIME, &m, t);
        }
        return;
    }
    default:
        return;
    }
}

void nav_ports_init(nav_ports_t *n, const hal_t *hal, board_link_t *link, nav_policy_t policy)
{
    memset(n, 0, sizeof(*n));
    n->hal = hal;
    n->link = link;
    n->policy = policy;
    vn200_parser_init(&n->vn, on_ins, n);
    sbp_parser_init(&n->sbp, on_sbp, n);
    n->next_status_us = hal->micros() + NAV_STATUS_PERIOD_US;
}

static void send_status(nav_ports_t *n, uint64_t now)
{
    uint64_t age = n->have_sbp ? (now - n->last_sbp_us) / 1000u : UINT16_MAX;
    aw_rtk_status_t st = {
        .sbp_frames_ok = n->sbp.frames,
        .sbp_crc_errors = n->sbp.crc_errors,
        .sbp_unhandled = n->sbp.undecoded + n->sbp.bad_length,
        .last_frame_age_ms = age > UINT16_MAX ? UINT16_MAX : (uint16_t)age,
        .num_sats = n->have_pos ? n->pos.num_sats : 0u,
        .fix_mode = n->have_pos ? n->pos.fix_mode : 0u,
    };
    (void)board_link_send(n->link, AW_ID_RTK_STATUS, &st, (uint32_t)now);
    if (n->policy == NAV_STATUS_ONLY) {
        if (n->have_pos) {
            (void)board_link_send(n->link, AW_ID_RTK_POS, &n->pos, (uint32_t)now);
        }
        if (n->have_gps_time) {
            (void)board_link_send(n->link, AW_ID_GPS_TIME, &n->gps_time, (uint32_t)now);
        }
    }
}

uint64_t nav_ports_poll(nav_ports_t *n)
{
    const hal_t *hal = n->hal;
    uint8_t buf[128];
    size_t got;
    n->now_us = hal->micros();
    while ((got = hal->uart_read(HAL_PORT_INS, buf, sizeof(buf))) > 0) {
        vn200_parser_feed(&n->vn, buf, got);
    }
    while ((got = hal->uart_read(HAL_PORT_RTK, buf, sizeof(buf))) > 0) {
        sbp_parser_feed(&n->sbp, buf, got);
    }
    if (n->now_us >= n->next_status_us) {
        send_status(n, n->now_us);
        n->next_status_us += NAV_STATUS_PERIOD_US;
        if (n->next_status_us <= n->now_us) {
            n->next_status_us = n->now_us + NAV_STATUS_PERIOD_US;
        }
    }
    return n->next_status_us;
}
