/* CRC-16/XMODEM (poly 0x1021, init 0, no reflection, no final xor): the CRC of both
 * VectorNav binary packets (appended big-endian) and SBP frames (appended
 * little-endian). Check value: crc16_xmodem("123456789") = 0x31C3. */
#ifndef AW_CRC16_XMODEM_H
#define AW_CRC16_XMODEM_H

#include <stddef.h>
#include <stdint.h>

uint16_t crc16_xmodem_update(uint16_t crc, const uint8_t *data, size_t len);

static inline uint16_t crc16_xmodem(const uint8_t *data, size_t len)
{
    return crc16_xmodem_update(0u, data, len);
}

#endif
