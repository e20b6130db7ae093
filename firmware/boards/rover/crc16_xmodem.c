/* CRC-16/XMODEM, nibble table: 32 bytes of flash, two lookups per byte. */
#include "crc16_xmodem.h"

static const uint16_t nibble_table[16] = {
    0x0000, 0x1021, 0x2042, 0x3063, 0x4084, 0x50a5, 0x60c6, 0x70e7,
    0x8108, 0x9129, 0xa14a, 0xb16b, 0xc18c, 0xd1ad, 0xe1ce, 0xf1ef,
};

uint16_t crc16_xmodem_update(uint16_t crc, const uint8_t *data, size_t len)
{
    for (size_t i = 0; i < len; i++) {
        crc = (uint16_t)((crc << 4) ^ nibble_table[((crc >> 12) ^ (data[i] >> 4)) & 0x0fu]);
        crc = (uint16_t)((crc << 4) ^ nibble_table[((crc >> 12) ^ (data[i] & 0x0fu)) & 0x0fu]);
    }
    return crc;
}
