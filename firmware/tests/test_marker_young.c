/* The Young 81000 ASCII line parser: values, z-down, stamps at the first byte, status
 * field, resync after garbage / overlong / malformed lines, lines split anywhere. */
#include <stdint.h>
#include <string.h>

#include "marker/young81000.h"
#include "test_algos.h"

static size_t feed_str(young_parser_t *p, const char *s, uint64_t t, young_sample_t *out,
                       size_t cap)
{
    size_t used = 0;
    size_t n = young_feed(p, (const uint8_t *)s, strlen(s), t, out, cap, &used);
    CHECK(used == strlen(s) || n == cap);
    return n;
}

static void test_young_parses_values_and_negates_w(void)
{
    young_parser_t p;
    young_init(&p);
    young_sample_t s[4];
    size_t n = feed_str(&p, "   1.25   -0.40    0.07   21.36\r\n", 1000u, s, 4);
    CHECK(n == 1);
    CHECK_NEAR(s[0].uvw_m_s[0], 1.25, 1e-6);
    CHECK_NEAR(s[0].uvw_m_s[1], -0.40, 1e-6);
    CHECK_NEAR(s[0].uvw_m_s[2], -0.07, 1e-6); /* W up -> z down */
    CHECK_NEAR(s[0].temp_c, 21.36, 1e-5);
    CHECK(s[0].status == 0u);
    CHECK(s[0].t_us == 1000u);
    CHECK(p.lines_ok == 1u && p.lines_bad == 0u);
}

static void test_young_stamps_the_first_byte_of_a_split_line(void)
{
    young_parser_t p;
    young_init(&p);
    young_sample_t s[4];
    CHECK(feed_str(&p, "  -3", 500u, s, 4) == 0);
    CHECK(feed_str(&p, ".50 2.00 -1.0", 800u, s, 4) == 0);
    CHECK(feed_str(&p, "0 18.00\r", 900u, s, 4) == 0);
    CHECK(feed_str(&p, "\n 0.00 0.00 0.00 20.00 7\r\n", 1200u, s, 4) == 2);
    CHECK(s[0].t_us == 500u);
    CHECK_NEAR(s[0].uvw_m_s[0], -3.5, 1e-6);
    CHECK_NEAR(s[0].uvw_m_s[2], 1.0, 1e-6);
    CHECK(s[1].t_us == 1200u);
    CHECK(s[1].status == 7u);
}

static void test_young_skips_bad_lines_and_resyncs(void)
{
    young_parser_t p;
    young_init(&p);
    young_sample_t s[8];
    char longline[200];
    memset(longline, '1', sizeof(longline));
    longline[sizeof(longline) - 2] = '\n';
    longline[sizeof(longline) - 1] = '\0';
    size_t n = 0;
    n += feed_str(&p, "1.0 2.0 3.0\r\n", 0u, s + n, 8 - n);            /* 3 fields */
    n += feed_str(&p, "1.0 2.x 3.0 4.0\r\n", 0u, s + n, 8 - n);        /* bad number */
    n += feed_str(&p, "1..0 2.0 3.0 4.0\r\n", 0u, s + n, 8 - n);       /* two points */
    n += feed_str(&p, "1.0 2.0 3.0 4.0 5.0 6.0\r\n", 0u, s + n, 8 - n); /* 6 fields */
    n += feed_str(&p, "1.0 2.0 3.0 4.0 2.5\r\n", 0u, s + n, 8 - n);    /* status 2.5 */
    n += feed_str(&p, longline, 0u, s + n, 8 - n);                      /* too long */
    n += feed_str(&p, "\x01\xff\xfa 1.0 2.0\r\n", 0u, s + n, 8 - n);    /* binary */
    CHECK(n == 0);
    CHECK(p.lines_bad == 7u);
    n = feed_str(&p, "0.50,0.25,-0.25,19.5\r\n", 42u, s, 8);           /* commas */
    CHECK(n == 1);
    CHECK(p.lines_ok == 1u);
    CHECK_NEAR(s[0].uvw_m_s[2], 0.25, 1e-6);
    CHECK(s[0].t_us == 42u);
}

static void test_young_keeps_lines_beyond_the_output_capacity(void)
{
    young_parser_t p;
    young_init(&p);
    const char *three = "1 0 0 20\r\n2 0 0 20\r\n3 0 0 20\r\n";
    young_sample_t s[2];
    size_t used = 0;
    size_t n = young_feed(&p, (const uint8_t *)three, strlen(three), 0u, s, 2, &used);
    CHECK(n == 2);
    CHECK(used < strlen(three));
    n = young_feed(&p, (const uint8_t *)three + used, strlen(three) - used, 0u, s, 2, &used);
    CHECK(n == 1);
    CHECK_NEAR(s[0].uvw_m_s[0], 3.0, 1e-6);
    CHECK(p.lines_ok == 3u);
}

int main(void)
{
    RUN(test_young_parses_values_and_negates_w);
    RUN(test_young_stamps_the_first_byte_of_a_split_line);
    RUN(test_young_skips_bad_lines_and_resyncs);
    RUN(test_young_keeps_lines_beyond_the_output_capacity);
    return ALGO_TEST_EXIT();
}
