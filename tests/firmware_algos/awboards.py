"""ctypes mirror of the firmware algorithm modules in build/native/libawboards.so.

`load()` builds the library with `make -C firmware awboards` when it is missing or
older than its sources (under a file lock, so parallel test workers build it once),
loads it, declares the function signatures and checks every mirrored struct's size
against the C `sizeof` (a header change without a matching change here fails loudly).
"""

from __future__ import annotations

import ctypes as C
import fcntl
import subprocess
from functools import cache
from pathlib import Path

REPO = Path(__file__).resolve().parents[2]
FIRMWARE = REPO / "firmware"
LIB = REPO / "build" / "native" / "libawboards.so"

LOSA_PIXELS = 128
LOSA_SENSORS = 4
MARKER_LEDS = 4

LOSA_PEAK_VALID = 0x01
LOSA_PEAK_SATURATED = 0x02
LOSA_PEAK_EDGE = 0x04
LOSA_PEAK_CENTROID = 0x08
LOSA_SLOT_CHANGED = 0x10
LOSA_SLOT_OUT_OF_RANGE = 0x20
LOSA_SLOT_RESET = 0x40


class Quat(C.Structure):
    _fields_ = [("w", C.c_float), ("x", C.c_float), ("y", C.c_float), ("z", C.c_float)]


class LosaPeakCfg(C.Structure):
    _fields_ = [("full_scale", C.c_uint16), ("sat_level", C.c_uint16), ("min_contrast", C.c_uint16)]


class LosaPeak(C.Structure):
    _fields_ = [
        ("pos_px", C.c_float),
        ("peak", C.c_uint16),
        ("background", C.c_uint16),
        ("flags", C.c_uint8),
        ("max_index", C.c_uint8),
    ]


class LosaSlotCfg(C.Structure):
    _fields_ = [("jump_px", C.c_float), ("lost_reset_frames", C.c_uint16)]


class LosaSlotState(C.Structure):
    _fields_ = [
        ("last_raw_px", C.c_float),
        ("lost_frames", C.c_uint16),
        ("slot", C.c_uint8),
        ("have_last", C.c_uint8),
        ("slot_changes", C.c_uint32),
        ("resets", C.c_uint32),
    ]


class LosaExposureCfg(C.Structure):
    _fields_ = [
        ("min_us", C.c_uint32),
        ("max_us", C.c_uint32),
        ("low_permille", C.c_uint16),
        ("high_permille", C.c_uint16),
        ("target_permille", C.c_uint16),
        ("max_step_up", C.c_uint16),
    ]


class LosaExposureState(C.Structure):
    _fields_ = [
        ("exposure_us", C.c_uint32),
        ("saturated_frames", C.c_uint32),
        ("weak_frames", C.c_uint32),
    ]


class LosaFrameCfg(C.Structure):
    _fields_ = [("peak", LosaPeakCfg), ("slot", LosaSlotCfg), ("exposure", LosaExposureCfg)]


class LosaFrameState(C.Structure):
    _fields_ = [
        ("slot", LosaSlotState * LOSA_SENSORS),
        ("exposure", LosaExposureState * LOSA_SENSORS),
    ]


class LosaSensorResult(C.Structure):
    _fields_ = [
        ("pos_px", C.c_float),
        ("raw_px", C.c_float),
        ("peak", C.c_uint16),
        ("background", C.c_uint16),
        ("exposure_us", C.c_uint32),
        ("next_exposure_us", C.c_uint32),
        ("slot", C.c_uint8),
        ("flags", C.c_uint8),
    ]


F3 = C.c_float * 3


class MarkerAttCfg(C.Structure):
    _fields_ = [
        ("still_gyro_rad_s", C.c_float),
        ("still_accel_m_s2", C.c_float),
        ("still_time_s", C.c_float),
        ("bias_tau_s", C.c_float),
    ]


class MarkerAtt(C.Structure):
    _fields_ = [
        ("q", Quat),
        ("bias_rad_s", F3),
        ("g_mag_m_s2", C.c_float),
        ("still_s", C.c_float),
        ("still", C.c_uint8),
    ]


class MarkerCfg(C.Structure):
    _fields_ = [
        ("att", MarkerAttCfg),
        ("calib_us", C.c_uint32),
        ("sweep_settle_us", C.c_uint32),
        ("feedback_timeout_us", C.c_uint32),
        ("max_dt_us", C.c_uint32),
        ("calib_moving_gyro_rad_s", C.c_float),
        ("calib_moving_accel_m_s2", C.c_float),
        ("sweep_intensity", C.c_float),
        ("target_peak", C.c_float),
        ("deadband", C.c_float),
        ("detect_peak", C.c_float),
        ("gain", C.c_float),
        ("min_intensity", C.c_float),
        ("max_intensity", C.c_float),
    ]


class MarkerState(C.Structure):
    _fields_ = [
        ("att", MarkerAtt),
        ("mode", C.c_int),
        ("mode_start_us", C.c_uint32),
        ("last_ir_us", C.c_uint32),
        ("last_imu_us", C.c_uint32),
        ("have_imu", C.c_uint8),
        ("calibrated", C.c_uint8),
        ("gyro_sum", F3),
        ("accel_sum", F3),
        ("calib_samples", C.c_uint32),
        ("calib_moving", C.c_uint8),
        ("sweep_weight", C.c_float * MARKER_LEDS),
        ("sweep_led_start_us", C.c_uint32),
        ("sweep_led", C.c_uint8),
        ("los_ref", F3),
        ("gravity_ref_m_s2", F3),
        ("active_led", C.c_uint8),
        ("intensity", C.c_float),
        ("calibrations", C.c_uint32),
        ("feedback_timeouts", C.c_uint32),
    ]


class MarkerOutput(C.Structure):
    _fields_ = [
        ("q", Quat),
        ("gravity_m_s2", F3),
        ("los", F3),
        ("gyro_bias_rad_s", F3),
        ("mode", C.c_uint8),
        ("active_led", C.c_uint8),
        ("still", C.c_uint8),
        ("intensity", C.c_float),
    ]


class Vn200Ins(C.Structure):
    _fields_ = [
        ("time_startup_ns", C.c_uint64),
        ("lla", C.c_double * 3),
        ("ypr_deg", F3),
        ("angular_rate_rad_s", F3),
        ("vel_ned_m_s", F3),
        ("accel_m_s2", F3),
        ("ins_status", C.c_uint16),
        ("group", C.c_uint8),
        ("present", C.c_uint8),
    ]


VN200_HANDLER = C.CFUNCTYPE(None, C.c_void_p, C.POINTER(Vn200Ins))


class Vn200Parser(C.Structure):
    _fields_ = [
        ("handler", VN200_HANDLER),
        ("ctx", C.c_void_p),
        ("n", C.c_size_t),
        ("packets", C.c_uint32),
        ("crc_errors", C.c_uint32),
        ("bad_headers", C.c_uint32),
        ("oversize", C.c_uint32),
        ("bytes_dropped", C.c_uint32),
        ("later_syncs", C.c_uint16),
        ("buf", C.c_uint8 * 512),
    ]


class SbpBaselineNed(C.Structure):
    _fields_ = [
        ("tow", C.c_uint32),
        ("n", C.c_int32),
        ("e", C.c_int32),
        ("d", C.c_int32),
        ("h_accuracy", C.c_uint16),
        ("v_accuracy", C.c_uint16),
        ("n_sats", C.c_uint8),
        ("flags", C.c_uint8),
    ]


class SbpPosLlh(C.Structure):
    _fields_ = [
        ("tow", C.c_uint32),
        ("lat", C.c_double),
        ("lon", C.c_double),
        ("height", C.c_double),
        ("h_accuracy", C.c_uint16),
        ("v_accuracy", C.c_uint16),
        ("n_sats", C.c_uint8),
        ("flags", C.c_uint8),
    ]


class SbpVelNed(SbpBaselineNed):
    pass


class SbpGpsTime(C.Structure):
    _fields_ = [
        ("wn", C.c_uint16),
        ("tow", C.c_uint32),
        ("ns_residual", C.c_int32),
        ("flags", C.c_uint8),
    ]


class SbpBaselineEcef(C.Structure):
    _fields_ = [
        ("tow", C.c_uint32),
        ("x", C.c_int32),
        ("y", C.c_int32),
        ("z", C.c_int32),
        ("accuracy", C.c_uint16),
        ("n_sats", C.c_uint8),
        ("flags", C.c_uint8),
    ]


class SbpDops(C.Structure):
    _fields_ = [
        ("tow", C.c_uint32),
        ("gdop", C.c_uint16),
        ("pdop", C.c_uint16),
        ("tdop", C.c_uint16),
        ("hdop", C.c_uint16),
        ("vdop", C.c_uint16),
        ("flags", C.c_uint8),
    ]


class SbpUtcTime(C.Structure):
    _fields_ = [
        ("flags", C.c_uint8),
        ("tow", C.c_uint32),
        ("year", C.c_uint16),
        ("month", C.c_uint8),
        ("day", C.c_uint8),
        ("hours", C.c_uint8),
        ("minutes", C.c_uint8),
        ("seconds", C.c_uint8),
        ("ns", C.c_uint32),
    ]


class SbpImuRaw(C.Structure):
    _fields_ = [
        ("tow", C.c_uint32),
        ("tow_f", C.c_uint8),
        ("acc_x", C.c_int16),
        ("acc_y", C.c_int16),
        ("acc_z", C.c_int16),
        ("gyr_x", C.c_int16),
        ("gyr_y", C.c_int16),
        ("gyr_z", C.c_int16),
    ]


class SbpUnion(C.Union):
    _fields_ = [
        ("baseline_ned", SbpBaselineNed),
        ("pos_llh", SbpPosLlh),
        ("vel_ned", SbpVelNed),
        ("gps_time", SbpGpsTime),
        ("baseline_ecef", SbpBaselineEcef),
        ("dops", SbpDops),
        ("utc_time", SbpUtcTime),
        ("imu_raw", SbpImuRaw),
    ]


class SbpMsg(C.Structure):
    _fields_ = [
        ("msg_type", C.c_uint16),
        ("sender", C.c_uint16),
        ("length", C.c_uint8),
        ("decoded", C.c_uint8),
        ("m", SbpUnion),
        ("payload", C.POINTER(C.c_uint8)),
    ]


SBP_HANDLER = C.CFUNCTYPE(None, C.c_void_p, C.POINTER(SbpMsg))


class SbpParser(C.Structure):
    _fields_ = [
        ("handler", SBP_HANDLER),
        ("ctx", C.c_void_p),
        ("n", C.c_size_t),
        ("frames", C.c_uint32),
        ("crc_errors", C.c_uint32),
        ("undecoded", C.c_uint32),
        ("bad_length", C.c_uint32),
        ("bytes_dropped", C.c_uint32),
        ("later_syncs", C.c_uint16),
        ("buf", C.c_uint8 * 263),
    ]


class RotorSpeedCfg(C.Structure):
    _fields_ = [("min_interval_us", C.c_uint32), ("max_interval_us", C.c_uint32)]


class RotorSpeed(C.Structure):
    _fields_ = [
        ("last_pulse_us", C.c_uint32),
        ("estimate_us", C.c_uint32),
        ("prev_interval_us", C.c_uint32),
        ("interval_us", C.c_uint32),
        ("have_pulse", C.c_uint8),
        ("agreed", C.c_uint8),
        ("outliers_in_row", C.c_uint8),
        ("have_early", C.c_uint8),
        ("early_us", C.c_uint32),
        ("pulses", C.c_uint32),
        ("glitches", C.c_uint32),
        ("missed", C.c_uint32),
    ]


class RotorSpeedOut(C.Structure):
    _fields_ = [
        ("speed_rad_s", C.c_float),
        ("interval_us", C.c_uint32),
        ("pulses", C.c_uint32),
        ("glitches", C.c_uint32),
        ("missed", C.c_uint32),
        ("valid", C.c_uint8),
    ]


class PwmCaptureCfg(C.Structure):
    _fields_ = [
        ("min_us", C.c_uint16),
        ("max_us", C.c_uint16),
        ("jump_us", C.c_uint16),
        ("timeout_us", C.c_uint32),
    ]


class PwmChannel(C.Structure):
    _fields_ = [
        ("rise_us", C.c_uint32),
        ("last_accept_us", C.c_uint32),
        ("period_us", C.c_uint32),
        ("width_us", C.c_uint16),
        ("candidate_us", C.c_uint16),
        ("have_rise", C.c_uint8),
        ("have_width", C.c_uint8),
        ("pulses", C.c_uint32),
        ("glitches", C.c_uint32),
    ]


class PwmChannelOut(C.Structure):
    _fields_ = [
        ("width_us", C.c_uint16),
        ("valid", C.c_uint8),
        ("period_us", C.c_uint32),
        ("glitches", C.c_uint32),
    ]


_MIRRORS = {
    "quat_t": Quat,
    "losa_peak_cfg_t": LosaPeakCfg,
    "losa_peak_t": LosaPeak,
    "losa_slot_cfg_t": LosaSlotCfg,
    "losa_slot_state_t": LosaSlotState,
    "losa_exposure_cfg_t": LosaExposureCfg,
    "losa_exposure_state_t": LosaExposureState,
    "losa_frame_cfg_t": LosaFrameCfg,
    "losa_frame_state_t": LosaFrameState,
    "losa_sensor_result_t": LosaSensorResult,
    "marker_att_cfg_t": MarkerAttCfg,
    "marker_att_t": MarkerAtt,
    "marker_cfg_t": MarkerCfg,
    "marker_state_t": MarkerState,
    "marker_output_t": MarkerOutput,
    "vn200_ins_t": Vn200Ins,
    "vn200_parser_t": Vn200Parser,
    "sbp_msg_t": SbpMsg,
    "sbp_parser_t": SbpParser,
    "rotor_speed_cfg_t": RotorSpeedCfg,
    "rotor_speed_t": RotorSpeed,
    "rotor_speed_out_t": RotorSpeedOut,
    "pwm_capture_cfg_t": PwmCaptureCfg,
    "pwm_channel_t": PwmChannel,
    "pwm_channel_out_t": PwmChannelOut,
}

P = C.POINTER
U16LINE = C.c_uint16 * LOSA_PIXELS

_SIGNATURES = {
    "losa_peak_default_cfg": (LosaPeakCfg, [C.c_uint]),
    "losa_peak_find": (None, [P(LosaPeakCfg), P(C.c_uint16), P(LosaPeak)]),
    "losa_slot_default_cfg": (LosaSlotCfg, []),
    "losa_slot_init": (None, [P(LosaSlotState)]),
    "losa_slot_update": (
        C.c_uint8,
        [P(LosaSlotState), P(LosaSlotCfg), P(LosaPeak), P(C.c_uint8), P(C.c_float)],
    ),
    "losa_exposure_default_cfg": (LosaExposureCfg, []),
    "losa_exposure_init": (None, [P(LosaExposureState), C.c_uint32, P(LosaExposureCfg)]),
    "losa_exposure_update": (
        C.c_uint32,
        [P(LosaExposureState), P(LosaExposureCfg), P(LosaPeak), C.c_uint16],
    ),
    "losa_frame_default_cfg": (LosaFrameCfg, [C.c_uint]),
    "losa_frame_init": (None, [P(LosaFrameState), P(LosaFrameCfg), C.c_uint32]),
    "losa_frame_process": (
        None,
        [P(LosaFrameState), P(LosaFrameCfg), P(U16LINE), P(LosaSensorResult)],
    ),
    "quat_identity": (Quat, []),
    "quat_mul": (Quat, [Quat, Quat]),
    "quat_normalize": (Quat, [Quat]),
    "quat_integrate": (Quat, [Quat, P(C.c_float), C.c_float]),
    "quat_rotate": (None, [Quat, P(C.c_float), P(C.c_float)]),
    "quat_rotate_inv": (None, [Quat, P(C.c_float), P(C.c_float)]),
    "marker_default_cfg": (MarkerCfg, []),
    "marker_init": (None, [P(MarkerState), P(MarkerCfg), C.c_uint32]),
    "marker_imu_step": (
        None,
        [P(MarkerState), P(MarkerCfg), C.c_uint32, P(C.c_float), P(C.c_float)],
    ),
    "marker_feedback": (None, [P(MarkerState), P(MarkerCfg), C.c_uint32, P(C.c_float)]),
    "marker_output": (None, [P(MarkerState), P(MarkerOutput)]),
    "marker_led_drive": (None, [P(MarkerState), P(C.c_float)]),
    "marker_lit_led": (C.c_uint, [P(MarkerState)]),
    "vn200_field_size": (C.c_uint, [C.c_uint, C.c_uint]),
    "vn200_parser_init": (None, [P(Vn200Parser), VN200_HANDLER, C.c_void_p]),
    "vn200_parser_feed": (None, [P(Vn200Parser), C.c_char_p, C.c_size_t]),
    "sbp_parser_init": (None, [P(SbpParser), SBP_HANDLER, C.c_void_p]),
    "sbp_parser_feed": (None, [P(SbpParser), C.c_char_p, C.c_size_t]),
    "crc16_xmodem_update": (C.c_uint16, [C.c_uint16, C.c_char_p, C.c_size_t]),
    "rotor_speed_default_cfg": (RotorSpeedCfg, []),
    "rotor_speed_init": (None, [P(RotorSpeed)]),
    "rotor_speed_pulse": (None, [P(RotorSpeed), P(RotorSpeedCfg), C.c_uint32]),
    "rotor_speed_get": (None, [P(RotorSpeed), P(RotorSpeedCfg), C.c_uint32, P(RotorSpeedOut)]),
    "pwm_capture_default_cfg": (PwmCaptureCfg, []),
    "pwm_channel_init": (None, [P(PwmChannel)]),
    "pwm_channel_edge": (None, [P(PwmChannel), P(PwmCaptureCfg), C.c_uint32, C.c_int]),
    "pwm_channel_get": (None, [P(PwmChannel), P(PwmCaptureCfg), C.c_uint32, P(PwmChannelOut)]),
    "awb_sizeof": (C.c_size_t, [C.c_char_p]),
}


def _build() -> None:
    LIB.parent.mkdir(parents=True, exist_ok=True)
    with open(LIB.parent / ".awboards.lock", "w") as lock:
        fcntl.flock(lock, fcntl.LOCK_EX)
        # make decides whether anything is out of date
        subprocess.run(
            ["make", "-s", "-C", str(FIRMWARE), "awboards"],
            check=True,
            stdout=subprocess.DEVNULL,
        )


@cache
def load() -> C.CDLL:
    _build()
    lib = C.CDLL(str(LIB))
    for name, (restype, argtypes) in _SIGNATURES.items():
        fn = getattr(lib, name)
        fn.restype = restype
        fn.argtypes = argtypes
    for cname, mirror in _MIRRORS.items():
        c_size = lib.awb_sizeof(cname.encode())
        if c_size != C.sizeof(mirror):
            raise AssertionError(
                f"ctypes mirror of {cname} is {C.sizeof(mirror)} bytes, C says {c_size}: "
                "update tests/firmware_algos/awboards.py"
            )
    return lib


def floats(values) -> C.Array:
    values = list(values)
    return (C.c_float * len(values))(*values)
