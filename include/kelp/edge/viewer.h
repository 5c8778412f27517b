/* kelp edge: kelp-viewer's web server (libmicrohttpd, in its own archive libkelp_viewer.a so
 * libkelp does not need it) and its replay of a recorded mission.
 *
 * The page (share/viewer/index.html, viewer.js, viewer.css, served from a document root) reads
 * a Server-Sent Events stream, GET /events: the first message is a snapshot of the model, each
 * later one the changes since the one before (kelp/viewer.h's JSON); "event: replay" messages
 * carry the replay state. POST /cmd?i=N presses command N (a configured button or action: the
 * page can name nothing else); POST /replay?op=play|pause|seek|speed&v=X steers a replay.
 * Both need the header "X-Kelp: 1", which a cross-site form cannot send.
 *
 * Threads: microhttpd runs a thread per connection. The model (kelp_viewer) belongs to the
 * caller's thread alone: it calls kelp_viewer_http_pump() often (every iteration), which
 * hands over the JSON the connections send (a ring of frames under a mutex) and answers their
 * snapshot requests; requests from the page (commands, replay steering) are queued for
 * kelp_viewer_http_next(). kelp_viewer_http_fd() becomes readable when something waits, so
 * an event loop can wake for it.
 *
 * Access: 127.0.0.1 by default. Any other bind address needs a token; every request must then
 * carry it (?token=, the X-Kelp-Token header, or the cookie the server sets when a request
 * with ?token= is accepted).
 */
#ifndef KELP_EDGE_VIEWER_H
#define KELP_EDGE_VIEWER_H

#include <stdbool.h>
#include <stddef.h>
#include <kelp/viewer.h>
#include <kelp/err.h>

#ifdef __cplusplus
extern "C" {
#endif

typedef struct kelp_viewer_http kelp_viewer_http;

typedef struct kelp_viewer_http_cfg {
    const char *bind;        /**< address to bind, NULL: 127.0.0.1 */
    unsigned port;           /**< 0: any free port (kelp_viewer_http_port tells) */
    const char *token;       /**< NULL or "": none (refused unless bound to 127.0.0.1) */
    const char *docroot;     /**< directory holding index.html, viewer.js, viewer.css */
    const char *image_path;  /**< background image served as /image, or NULL */
    double push_period;      /**< wall seconds between change frames (0: 0.2) */
} kelp_viewer_http_cfg;

typedef enum kelp_viewer_req_kind {
    KELP_VIEWER_REQ_CMD = 1,    /**< press command idx */
    KELP_VIEWER_REQ_PLAY,
    KELP_VIEWER_REQ_PAUSE,
    KELP_VIEWER_REQ_SEEK,       /**< value: seconds from the start of the log */
    KELP_VIEWER_REQ_SPEED,      /**< value: 1..20 */
} kelp_viewer_req_kind;

typedef struct kelp_viewer_req {
    kelp_viewer_req_kind kind;
    unsigned idx;
    double value;
} kelp_viewer_req;

/** Start serving. @return NULL with the reason in d on failure. */
kelp_viewer_http *kelp_viewer_http_start(const kelp_viewer_http_cfg *cfg, kelp_diag *d);
/** The port bound. */
unsigned kelp_viewer_http_port(const kelp_viewer_http *h);
/** Readable when a request or a snapshot request waits (drained by pump / next). */
int kelp_viewer_http_fd(const kelp_viewer_http *h);
/** Model thread: send the changes when push_period has passed (or force), answer snapshot
 *  requests. now/rate: as kelp_viewer_json_*. @return frames pushed (0 or 1), <0 on error. */
KELP_MUST_CHECK int kelp_viewer_http_pump(kelp_viewer_http *h, const kelp_viewer *v, double now, double rate, bool force);
/** Model thread: push a replay state message ({"t0":..,"t1":..,"t":..,"playing":..,"speed":..}). */
KELP_MUST_CHECK int kelp_viewer_http_push_event(kelp_viewer_http *h, const char *event, const char *json);
/** Model thread: the next request from the page. @return 1 with one, 0 none. */
KELP_MUST_CHECK int kelp_viewer_http_next(kelp_viewer_http *h, kelp_viewer_req *out);
/** Connections streaming events now. */
unsigned kelp_viewer_http_clients(const kelp_viewer_http *h);
/** Bytes of the last snapshot and change frame (for the status report). */
void kelp_viewer_http_sizes(const kelp_viewer_http *h, size_t *snapshot, size_t *frame, unsigned long *frames);
void kelp_viewer_http_stop(kelp_viewer_http *h);

/** Read a pMarineViewer .info file (lat_north, lat_south, lon_east, lon_west; "//" comments).
 *  @return 0, <0 with the reason in d. */
KELP_MUST_CHECK int kelp_viewer_read_info(const char *path, double *lat_n, double *lat_s, double *lon_e, double *lon_w, kelp_diag *d);

/** The page's files: share/viewer beside the program in the build tree (<bin>/../../share/viewer),
 *  installed (<bin>/../share/kelp/viewer), or $KELP_VIEWER_DOCROOT. @return 0 or KELP_ERR_NOTFOUND. */
KELP_MUST_CHECK int kelp_viewer_docroot(char *buf, size_t cap);

/** pMarineViewer's tiff_file (relative to the mission file's directory when not absolute): the
 *  image to serve (a .png, .jpg or .jpeg of the same name if one exists, else the file itself)
 *  and its .info file. @return 0 or KELP_ERR_NOTFOUND. */
KELP_MUST_CHECK int kelp_viewer_image_files(const char *tiff, const char *mission_path, char *image, size_t icap, char *info,
                            size_t infocap);

/** kelp-viewer --log RUN.lcm [--port N] [--bind A --token T] [--docroot D] [--speed S] [--paused]
 *  [mission.moos [NAME]]: replays a recorded mission (kelp-record's LCM log or an .alog) into the
 *  page, with a time slider, play/pause and speed; no bus. The mission, when given, supplies the
 *  datum and the viewer block (NAME, else kelp-viewer, else pMarineViewer: tiff_file, trails...). Runs until SIGINT/SIGTERM. @return exit status. */
KELP_MUST_CHECK int kelp_viewer_replay_main(int argc, char **argv);

#ifdef __cplusplus
}
#endif

#endif
