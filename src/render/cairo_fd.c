/* springpend (internal): cairo's output to a file descriptor. See cairo_fd.h. */
#include <cairo-pdf.h>
#include <errno.h>
#include <stdlib.h>
#include <time.h>
#include <unistd.h>

#include "cairo_fd.h"
#include "springpend/common.h"

cairo_status_t sp_cairo_fd_write(void *closure, const unsigned char *data, unsigned int length)
{
    struct sp_cairo_fd *k = closure;
    while (length && !k->err) {
        ssize_t n = write(k->fd, data, length);
        if (n < 0 && errno == EINTR)
            continue;
        if (n <= 0)
            k->err = n < 0 ? errno : EIO;
        else
            data += n, length -= (unsigned int)n;
    }
    return k->err ? CAIRO_STATUS_WRITE_ERROR : CAIRO_STATUS_SUCCESS;
}

int sp_cairo_pdf_date(cairo_surface_t *pdf)
{
    const char *env = getenv("SOURCE_DATE_EPOCH");
    char iso[32] = ""; /* empty: cairo writes no /CreationDate */
    if (env) {
        char *end;
        errno = 0;
        long long t = strtoll(env, &end, 10);
        struct tm tm;
        time_t tt = (time_t)t;
        if (!*env || *end || errno || t < 0 || t > 253402300799LL || *env < '0' || *env > '9' ||
            !gmtime_r(&tt, &tm)) {
            sp_log_error("SOURCE_DATE_EPOCH='%s' is not a time; expected whole seconds since "
                         "1970-01-01 UTC, 0 to 253402300799 (or leave it unset: no date is written)",
                         env);
            return SP_E_INPUT;
        }
        strftime(iso, sizeof iso, "%Y-%m-%dT%H:%M:%SZ", &tm);
    }
    cairo_pdf_surface_set_metadata(pdf, CAIRO_PDF_METADATA_CREATE_DATE, iso);
    return 0;
}
