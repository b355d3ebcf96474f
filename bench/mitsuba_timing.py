"""Times Mitsuba 3 renders the way the benches compare them with vastray's `render_seconds`: four
renders of a loaded scene (the first compiles its kernels), each evaluated and synchronized; the
later three give min and median. Returns those figures and the last image. Also the benches'
one camera (perspective_sensor)."""
import time


def perspective_sensor(mi, eye, target, w, h, spp, fov=45, **film):
    """vastray's pinhole camera (y up) as a Mitsuba sensor: vertical fov in degrees, a box filter,
    an independent sampler of spp samples; `film` adds hdrfilm fields (pixel_format, ...)."""
    return {
        "type": "perspective", "fov": fov, "fov_axis": "y",
        "to_world": mi.ScalarTransform4f().look_at(origin=eye, target=target, up=[0, 1, 0]),
        "film": {"type": "hdrfilm", "width": w, "height": h, "rfilter": {"type": "box"}, **film},
        "sampler": {"type": "independent", "sample_count": spp},
    }


def time_renders(mi, dr, scene, spp, rounds=4):
    times, img = [], None
    for i in range(rounds):
        t = time.perf_counter()
        img = mi.render(scene, spp=spp, seed=i)
        dr.eval(img)
        dr.sync_thread()
        times.append(time.perf_counter() - t)
    later = sorted(times[1:])
    return {"first_render_s": round(times[0], 3), "render_s_min": round(later[0], 4),
            "render_s_median": round(later[len(later) // 2], 4)}, img
