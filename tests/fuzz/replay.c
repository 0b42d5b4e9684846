/* springpend fuzzing: runs fuzz_scene.c's target once on each file named,
 * or on each file of each folder named, without libFuzzer, so the seed
 * corpus and past crashes are tests in every build (the sanitizer build
 * included). Prints TAP. */
#include <dirent.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "../unit/tap.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

static void run_file(const char *path)
{
    FILE *fp = fopen(path, "rb");
    uint8_t *data = NULL;
    long size = -1;
    if (fp && fseek(fp, 0, SEEK_END) == 0 && (size = ftell(fp)) >= 0 && fseek(fp, 0, SEEK_SET) == 0)
        data = malloc((size_t)size + 1);
    int read_ok = data && fread(data, 1, (size_t)size, fp) == (size_t)size;
    if (fp)
        fclose(fp);
    /* A crash aborts the whole run; reaching the next line is the test. */
    if (read_ok)
        LLVMFuzzerTestOneInput(data, (size_t)size);
    sp_tap_ok(read_ok, "%s (%ld bytes) parsed without a crash", path, size);
    free(data);
}

static int by_name(const struct dirent **a, const struct dirent **b)
{
    return strcmp((*a)->d_name, (*b)->d_name);
}

int main(int argc, char **argv)
{
    for (int i = 1; i < argc; i++) {
        struct stat st;
        struct dirent **list;
        if (stat(argv[i], &st) != 0 || !S_ISDIR(st.st_mode)) {
            run_file(argv[i]);
            continue;
        }
        int n = scandir(argv[i], &list, NULL, by_name);
        for (int j = 0; j < n; j++) {
            char path[4096];
            snprintf(path, sizeof(path), "%s/%s", argv[i], list[j]->d_name);
            if (list[j]->d_name[0] != '.' && strcmp(list[j]->d_name, "README") &&
                stat(path, &st) == 0 && S_ISREG(st.st_mode))
                run_file(path);
            free(list[j]);
        }
        free(n > 0 ? list : NULL);
    }
    return sp_tap_done();
}
