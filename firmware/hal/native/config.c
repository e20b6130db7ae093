/* config.c — native persistent configuration: a 2 KiB image like the MK20's
 * FlexRAM EEPROM (erased bytes read 0xFF), optionally backed by a file
 * (--config PATH) rewritten on every change. */
#include <errno.h>
#include <stdio.h>
#include <string.h>

#include "native.h"

#define CONFIG_SIZE 2048u

static uint8_t image[CONFIG_SIZE];
static const char *backing;
static bool loaded;

static void ensure_loaded(void)
{
    if (!loaded) {
        memset(image, 0xFF, sizeof(image));
        loaded = true;
    }
}

bool config_open(const char *path, char *err, size_t err_len)
{
    ensure_loaded();
    backing = path;
    FILE *f = fopen(path, "rb");
    if (f == NULL) {
        if (errno == ENOENT) {
            return true; /* a fresh board: everything erased */
        }
        snprintf(err, err_len, "--config %s: %s", path, strerror(errno));
        return false;
    }
    size_t n = fread(image, 1, sizeof(image), f);
    fclose(f);
    if (n != sizeof(image)) {
        snprintf(err, err_len, "--config %s: %zu bytes, expected %u", path, n, CONFIG_SIZE);
        return false;
    }
    return true;
}

bool config_read(uint32_t offset, void *buf, size_t len)
{
    ensure_loaded();
    if (offset > CONFIG_SIZE || len > CONFIG_SIZE - offset) {
        return false;
    }
    memcpy(buf, &image[offset], len);
    return true;
}

bool config_write(uint32_t offset, const void *buf, size_t len)
{
    ensure_loaded();
    if (offset > CONFIG_SIZE || len > CONFIG_SIZE - offset) {
        return false;
    }
    memcpy(&image[offset], buf, len);
    if (backing == NULL) {
        return true;
    }
    FILE *f = fopen(backing, "wb");
    if (f == NULL) {
        return false;
    }
    bool ok = fwrite(image, 1, sizeof(image), f) == sizeof(image);
    return (fclose(f) == 0) && ok;
}
