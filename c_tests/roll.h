/* Camera roll as Qu et al. 2003 render it: the view without roll, over a window that
 * covers the rolled one, then texture-mapped into the image turned by the roll (their
 * column-coherent traversal needs image columns that stay vertical planes). The other
 * way is to trace the rolled camera's rays directly, which a per-pixel ray caster does
 * at no extra cost. Both renderers compare the two: pixel error and frame time. */
#ifndef HFCAST_ROLL_H
#define HFCAST_ROLL_H

#include "render_common.h"

typedef struct roll_view {
    gpu unrolled; /* the unrolled render (its w, h: the last render's size) */
    int side;     /* its textures' side: the image's diagonal, so any roll fits */
    GLuint prog;  /* the texture-mapping pass */
} roll_view;

/* What roll_measure found for one roll. */
typedef struct roll_result {
    int pixels, unrolled_pixels; /* the image's, and the unrolled render's */
    int hit_differ;              /* pixels where one image hits and the other misses */
    int color_differ;            /* pixels whose colour differs by more than 8/255 */
    double color_mean;           /* mean absolute colour difference, 0..255 */
    int unturned;                /* hit/miss flips of the unturned unrolled image */
    double direct_ms, mapped_ms; /* median frame times: rolled rays; unrolled + mapping */
} roll_result;

/* The roll pass and an unrolled render target for images of g's size. 0, or -1. */
int roll_init(roll_view *r, const scene *s, const gpu *g);
void roll_free(roll_view *r);

/* The unrolled window (half extents on the view plane) and its size in pixels, at the
 * pixel pitch of a w x h image of `c`: the bounding box of the rolled window. At roll
 * 0 it is make_rays' window and w x h exactly. */
void roll_window(const camera *c, int w, int h, float half[2], int size[2]);

/* Renders `c` (its roll included) the mapped way into g's frame: the unrolled view,
 * then the texture-mapping pass. `rays` holds room for the unrolled render's rays. */
void roll_render_mapped(roll_view *r, gpu *g, const scene *s, method_cfg cfg, const camera *c,
                        hf_ray *rays);

/* Renders `c` both ways `reps` times into g (the direct image last in `direct`, the
 * mapped one in `mapped`) and compares them; and the camera without its roll, to count
 * what the mapping turns. Leaves g's rays those of `c`. */
roll_result roll_measure(roll_view *r, gpu *g, const scene *s, method_cfg cfg, const camera *c,
                         int reps, frame *direct, frame *mapped);

/* Whether a roll of `degrees` measured `res` as it should: at 0 (and 90, where the
 * pixel grids align) the two images are one; turned, the mapped one resamples the
 * unrolled render (nearest: up to half a pixel off), so silhouettes and the shading of
 * detail finer than a pixel change: at most 2 % of the pixels may flip between hit and
 * miss, at most a quarter of those that flip against the unturned image (what the
 * mapping pass does), and the mean colour error stays under 16/255 (7.3 on the
 * Jacksboro DEM at 256 x 192, whose texels are smaller than the pixels). */
int roll_ok(const roll_result *res, int degrees);

#endif
