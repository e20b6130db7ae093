/*
 * sim_proto.h — the record layout of the native board <-> hil_sim channel.
 * The normative description is docs/sim-channel.md; hil_sim/boards/channel.py
 * mirrors these numbers (a test parses this file and compares).
 *
 * Transport: AF_UNIX SOCK_SEQPACKET. Each packet holds whole records, at most
 * SIM_MAX_PACKET bytes. Every record starts with a 16-byte little-endian header:
 *   u8 type | u8 chan | u16 len (header + body) | u32 reserved (0) | u64 t_us
 * where t_us is simulator time in µs.
 */
#ifndef AW_SIM_PROTO_H
#define AW_SIM_PROTO_H

#define SIM_MAGIC 0x43535741u /* "AWSC" little endian */
#define SIM_VERSION 1u
#define SIM_MAX_PACKET 131072u
#define SIM_HEADER_LEN 16u

/* simulator -> board */
#define SIM_ADVANCE 0x01u  /* stepped: run to t_us, then answer IDLE; last record of a packet */
#define SIM_LINE 0x02u     /* chan = array 0..3; f32 rate[128] (counts/µs), f32 dark[128] (counts) */
#define SIM_IMU 0x03u      /* chan = IMU 0; f32 gyro_rad_s[3], accel_m_s2[3], mag_ut[3], temp_c */
#define SIM_EDGE 0x04u     /* chan = hal_capture_t; u8 level, 7 bytes pad */
#define SIM_UART 0x05u     /* chan = hal_port_t; the bytes the peer sent (port mapped to "sim") */
#define SIM_RESET 0x06u    /* reset the board at t_us (reset pin) */

/* board -> simulator */
#define SIM_HELLO 0x81u    /* u32 magic, u16 version, u8 mode (1 stepped, 2 wall), u8 board_id,
                              char name[16], u32 boot_count */
#define SIM_IDLE 0x82u     /* stepped: reached t_us; last record of the reply */
#define SIM_PWM 0x83u      /* chan = hal_pwm_t; u16 duty (0..65535), u16 pad */
#define SIM_UART_TX 0x84u  /* chan = hal_port_t; bytes the board sent (port mapped to "sim") */
#define SIM_BOOT 0x85u     /* u8 cause (hal_reset_cause_t), 3 pad, u32 boot_count */

#define SIM_LINE_BODY (2u * 128u * 4u)
#define SIM_IMU_BODY (10u * 4u)
#define SIM_EDGE_BODY 8u
#define SIM_HELLO_BODY 28u
#define SIM_PWM_BODY 4u
#define SIM_BOOT_BODY 8u

#endif /* AW_SIM_PROTO_H */
