/* Where a scene's referenced files may be (docs/SCENE_FORMAT.md, "Where
 * referenced files may be"): every file a scene or model names — a mesh, an
 * MTL file and its maps, a glTF buffer or image, a spectrum file, an include,
 * a texture, an environment map — must resolve (after "..", symbolic links
 * and, for URIs, percent-decoding) to a path under
 *   - the root: the folder of the file named on the command line,
 *   - a folder the user allows (render --allow-path DIR, repeatable),
 *   - or the project's own data (its spectra/ and scenes/ folders).
 * A reader never opens such a file by its name: it asks spm_path_check for
 * an spm_file and opens that (spm_path_fopen, or a library given its .path),
 * so tests/cli_paths.sh can tell by grep that no reader goes around it. */
#ifndef SPM_PATHS_H
#define SPM_PATHS_H
#include "util.h"
#ifdef __cplusplus
extern "C" {
#endif

#define SPM_PATH_MAX 4096

/* A path that passed the rule: `path` absolute, "." and ".." resolved, and
 * every symbolic link of the part that exists followed, to open; `shown` as
 * the reference was joined to its folder, for messages. */
typedef struct {
    char path[SPM_PATH_MAX];
    char shown[SPM_PATH_MAX];
} spm_file;

/* The root becomes the folder of `file`, the file named on the command line
 * (spm_scene_load calls it for the file it is given), which *top then holds.
 * 1 with err when the folder cannot be resolved. */
int spm_paths_set_root(const char *file, spm_file *top, spm_error *err);
/* --allow-path DIR: one more folder references may lead into. It must exist
 * and be a folder; 1 with err naming it otherwise. */
int spm_paths_allow(const char *dir, spm_error *err);
/* Forgets the allowed folders (not the root). */
void spm_paths_clear_allowed(void);

/* The reference `ref`, as written at `where` ("scene.txt:3:6",
 * "car.gltf: buffers[0].uri"), relative to the folder `dir` unless it is
 * absolute: 0 with *out set when it resolves under the root, an allowed
 * folder or the project's data; 1 with err otherwise, naming where, the
 * reference and the option that would allow it (exit 2). A file that does
 * not exist is checked by where it would be: the caller says it is missing. */
int spm_path_check(const char *dir, const char *ref, const char *where, spm_file *out,
                   spm_error *err);
/* The same for a path already joined to its folder (a reference's folder is
 * the referencing file's: spm_path_dir gives it). */
int spm_path_check_joined(const char *path, const char *where, spm_file *out, spm_error *err);
/* The folder of a file's path ("." for a bare name), into buf. */
const char *spm_path_dir(const char *file, char *buf, size_t size);

/* Opens a checked path for reading (spm_fopen_input's test hook applies). */
FILE *spm_path_fopen(const spm_file *p, const char *mode);

/* RFC 3986 percent-decoding of a URI's path ("%2e%2e/a%20b" -> "../a b"),
 * into out: 1 when it holds a malformed escape or decodes to a NUL byte. */
int spm_uri_decode(const char *uri, char *out, size_t size);

#ifdef __cplusplus
}
#endif
#endif
