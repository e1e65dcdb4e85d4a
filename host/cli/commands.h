/* The sub-commands of the specmip program. Each returns the process exit code
 * (util.h: 0 ok, 1 runtime failure, 2 usage/input error, 130 interrupted).
 * argv[0] is the sub-command's name. */
#ifndef SPM_COMMANDS_H
#define SPM_COMMANDS_H
int spm_cmd_render(int argc, char **argv);
int spm_cmd_spectrum(int argc, char **argv);
int spm_cmd_devices(int argc, char **argv);
int spm_cmd_compare(int argc, char **argv);
int spm_cmd_bench(int argc, char **argv);
int spm_cmd_modes(int argc, char **argv);
#endif
