/* Image files: float round trip, 8-bit decoding, and that a failed write never
 * damages an existing file or leaves a temporary behind. */
#include <dirent.h>
#include <signal.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <sys/wait.h>
#include <unistd.h>
#include "image_io.h"
#include "testutil.h"

static char dir[256];

static const char *in_dir(const char *name)
{
    static char buf[512];
    snprintf(buf, sizeof buf, "%s/%s", dir, name);
    return buf;
}

static int temporaries_left(void)
{
    int n = 0;
    DIR *d = opendir(dir);
    struct dirent *e;
    while (d && (e = readdir(d)))
        n += strstr(e->d_name, ".spmtmp") != NULL;
    if (d)
        closedir(d);
    return n;
}

/* Float files keep every float32 bit: negative, > 1, tiny and huge values. */
static void float_round_trip(const char *ext)
{
    enum { W = 5, H = 3 };
    float px[W * H * 3];
    const float special[] = {-0.5f, 1e6f, 3.14159274f, 1e-30f, -123.25f, 1.0f, 0.0f, 2.5f};
    for (int i = 0; i < W * H * 3; i++)
        px[i] = special[i % 8] * (float)(1 + i / 8);
    char name[32];
    snprintf(name, sizeof name, "round%s", ext);
    spm_error err = {{0}};
    CHECK(spm_image_write(in_dir(name), W, H, px, SPM_PIXEL_FLOAT, &err) == 0, "%s", err.msg);
    spm_image img;
    CHECK(spm_image_read(in_dir(name), &img, &err) == 0, "%s", err.msg);
    CHECK(img.width == W && img.height == H, "%s size %dx%d", ext, img.width, img.height);
    if (img.rgb && img.width == W && img.height == H)
        CHECK(!memcmp(img.rgb, px, sizeof px), "%s: float pixels changed in the round trip", ext);
    spm_image_free(&img);
}

/* 8-bit files hold sRGB-encoded values and are decoded to linear on reading. */
static void png_decoding(void)
{
    unsigned char px[4 * 3] = {0, 10, 50, 128, 188, 255, 1, 2, 3, 200, 100, 250};
    spm_error err = {{0}};
    CHECK(spm_image_write(in_dir("codes.png"), 4, 1, px, SPM_PIXEL_UINT8, &err) == 0, "%s", err.msg);
    spm_image img;
    CHECK(spm_image_read(in_dir("codes.png"), &img, &err) == 0, "%s", err.msg);
    for (int i = 0; img.rgb && i < 12; i++) {
        double v = px[i] / 255.0;  /* IEC 61966-2-1 decoding, written out independently */
        double lin = v <= 0.04045 ? v / 12.92 : pow((v + 0.055) / 1.055, 2.4);
        /* float storage of the decoded value: relative 1e-6 covers it */
        CHECK_NEAR(img.rgb[i], lin, 1e-6 * lin + 1e-9, "decoded 8-bit value");
    }
    spm_image_free(&img);
}

static void write_rejects(void)
{
    float px[3] = {1, 2, 3};
    spm_error err = {{0}};
    CHECK(spm_image_write(in_dir("no-such-dir/x.exr"), 1, 1, px, SPM_PIXEL_FLOAT, &err) != 0,
          "writing into a missing directory succeeded");
    CHECK(strstr(err.msg, "no-such-dir/x.exr") != NULL, "message names the file: %s", err.msg);
    CHECK(spm_image_write(in_dir("x.nosuchformat"), 1, 1, px, SPM_PIXEL_FLOAT, &err) != 0,
          "unknown extension accepted");
    CHECK(temporaries_left() == 0, "a temporary file was left behind");
}

static void read_rejects(void)
{
    FILE *f = fopen(in_dir("garbage.exr"), "wb");
    fputs("this is not an image\n", f);
    fclose(f);
    spm_image img;
    spm_error err = {{0}};
    CHECK(spm_image_read(in_dir("garbage.exr"), &img, &err) != 0, "garbage read as an image");
    CHECK(strstr(err.msg, "garbage.exr") != NULL, "message names the file: %s", err.msg);
    CHECK(spm_image_read(in_dir("missing.exr"), &img, &err) != 0, "missing file read");
    CHECK(strstr(err.msg, "missing.exr") != NULL, "message names the file: %s", err.msg);
}

/* A write that fails half-way (the file size limit stops it, as a full disk would)
 * leaves the existing file as it was. */
static void failed_write_keeps_old_file(void)
{
    enum { W = 256, H = 256 };
    const char *path = in_dir("keep.exr");
    float old[3 * 4] = {0.25f, -1, 7, 0.5f, 0.5f, 0.5f, 9, 8, 7, 1, 2, 3};
    spm_error err = {{0}};
    CHECK(spm_image_write(path, 2, 2, old, SPM_PIXEL_FLOAT, &err) == 0, "%s", err.msg);
    struct stat before;
    stat(path, &before);

    /* Noise does not compress: about 786 kB of floats, far past the limit. */
    float *noise = malloc(sizeof(float) * W * H * 3);
    unsigned s = 12345;
    for (int i = 0; i < W * H * 3; i++)
        noise[i] = (float)((s = s * 1103515245u + 12345u) >> 8) / 16777216.0f;
    struct rlimit saved, small;
    getrlimit(RLIMIT_FSIZE, &saved);
    small = saved;
    small.rlim_cur = 64 * 1024;
    signal(SIGXFSZ, SIG_IGN);
    setrlimit(RLIMIT_FSIZE, &small);
    int rc = spm_image_write(path, W, H, noise, SPM_PIXEL_FLOAT, &err);
    setrlimit(RLIMIT_FSIZE, &saved);
    free(noise);
    CHECK(rc != 0, "a write past the file size limit reported success");
    CHECK(strstr(err.msg, "keep.exr") != NULL, "message names the file: %s", err.msg);

    spm_image img;
    CHECK(spm_image_read(path, &img, &err) == 0, "old file unreadable after failed write: %s", err.msg);
    CHECK(img.width == 2 && img.height == 2 && !memcmp(img.rgb, old, sizeof old),
          "old file changed by a failed write");
    spm_image_free(&img);
    CHECK(temporaries_left() == 0, "a failed write left its temporary file");

    /* A read-only directory stops the write before anything is written. Root
     * ignores permissions, so the write is tried by this program run again
     * (a fresh process: OpenImageIO's threads do not survive a fork) as
     * nobody (65534) when run as root: the refusal any user gets. */
    chmod(dir, 0555);
    pid_t pid = fork();
    if (pid == 0) {
        execl("/proc/self/exe", "test_image_io", "--write-as-nobody", path, (char *)NULL);
        _exit(4);
    }
    int status = -1;
    CHECK(pid > 0 && waitpid(pid, &status, 0) == pid, "fork for the read-only write");
    chmod(dir, 0755);
    CHECK(WIFEXITED(status) && WEXITSTATUS(status) < 3, "could not run as nobody (status %d)", status);
    CHECK(WIFEXITED(status) && WEXITSTATUS(status) == 0,
          "write into a read-only directory succeeded (status %d)", status);
    CHECK(spm_image_read(path, &img, &err) == 0 && img.width == 2 &&
              !memcmp(img.rgb, old, sizeof old), "old file lost or changed");
    spm_image_free(&img);
    CHECK(temporaries_left() == 0, "the refused write left a temporary file");
}

/* The child of the read-only case: exit 0 if the write into PATH is refused,
 * 1 if it succeeds, 3 if it cannot become nobody. */
static int write_as_nobody(const char *path)
{
    if (geteuid() == 0 && (setgid(65534) != 0 || setuid(65534) != 0))
        return 3;
    float px[3] = {1, 2, 3};
    spm_error err = {{0}};
    return spm_image_write(path, 1, 1, px, SPM_PIXEL_FLOAT, &err) != 0 ? 0 : 1;
}

int main(int argc, char **argv)
{
    if (argc == 3 && !strcmp(argv[1], "--write-as-nobody"))
        return write_as_nobody(argv[2]);
    snprintf(dir, sizeof dir, "/tmp/spm_test_image_io.XXXXXX");
    if (!mkdtemp(dir)) {
        perror("mkdtemp");
        return 1;
    }
    float_round_trip(".exr");
    float_round_trip(".tif");
    png_decoding();
    write_rejects();
    read_rejects();
    failed_write_keeps_old_file();
    char cmd[300];
    snprintf(cmd, sizeof cmd, "rm -rf '%s'", dir);
    if (system(cmd) != 0)
        fprintf(stderr, "could not remove %s\n", dir);
    TEST_END();
}
