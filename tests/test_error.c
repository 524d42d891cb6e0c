/* The error funnel: messages, names and exit codes. */
#include <string.h>

#include "harness.h"
#include "rad_error.h"

TEST(error_raise_records_message_and_returns_status)
{
    rad_error_clear();
    CHECK(strcmp(rad_error_message(), "") == 0);
    rad_status st = RAD_ERROR(RAD_EINPUT, "scene.obj:%d:%d: NaN coordinate", 12, 7);
    CHECK(st == RAD_EINPUT);
    CHECK(strcmp(rad_error_message(), "scene.obj:12:7: NaN coordinate") == 0);
    CHECK(strstr(rad_error_where(), "test_error.c:") != NULL);
    rad_error_clear();
    CHECK(rad_error_message()[0] == '\0');
}

TEST(error_every_status_has_a_distinct_name)
{
    for (int a = 0; a < RAD_STATUS_COUNT; a++) {
        const char *na = rad_strerror((rad_status)a);
        CHECK(na && *na && strcmp(na, "unknown status") != 0);
        for (int b = a + 1; b < RAD_STATUS_COUNT; b++)
            CHECK(strcmp(na, rad_strerror((rad_status)b)) != 0);
    }
    CHECK(strcmp(rad_strerror(RAD_STATUS_COUNT), "unknown status") == 0);
    CHECK(strcmp(rad_strerror((rad_status)-1), "unknown status") == 0);
}

TEST(error_exit_codes_follow_the_contract)
{
    CHECK(rad_status_exit_code(RAD_OK) == 0);
    CHECK(rad_status_exit_code(RAD_EINVAL) == 2);
    CHECK(rad_status_exit_code(RAD_EINPUT) == 2);
    CHECK(rad_status_exit_code(RAD_ETOOBIG) == 2);
    CHECK(rad_status_exit_code(RAD_ENOMEM) == 1);
    CHECK(rad_status_exit_code(RAD_ESINGULAR) == 1);
    CHECK(rad_status_exit_code(RAD_ENUMERIC) == 1);
}
