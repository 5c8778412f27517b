/* kelp edge: a mission file read from disk (owns the text and the parse). The parser itself
 * is core: include/kelp/mission.h. */
#ifndef KELP_EDGE_MISSION_H
#define KELP_EDGE_MISSION_H

#include <kelp/mission.h>

#ifdef __cplusplus
extern "C" {
#endif

/** A mission loaded from a file (edge, libkelp.a): owns the text and the nodes. */
typedef struct kelp_mission_file {
    char path[512];
    char *text;
    kelp_mission m;
    char error[768];     /**< "file:line: reason" on failure */
} kelp_mission_file;

/** Read and parse a file. @return 0, or <0 with f->error set to "path:line: reason". */
KELP_MUST_CHECK int kelp_mission_load(kelp_mission_file *f, const char *path);
/** Parse text held in memory (copied) with a name for messages. */
KELP_MUST_CHECK int kelp_mission_load_text(kelp_mission_file *f, const char *name, const char *text, size_t len);
void kelp_mission_free(kelp_mission_file *f);

#ifdef __cplusplus
}
#endif

#endif
