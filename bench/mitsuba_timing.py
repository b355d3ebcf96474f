"""Times Mitsuba 3 renders the way the benches compare them with vastray's `render_seconds`: four
renders of a loaded scene (the first compiles its kernels), each evaluated and synchronized; the
later three give min and median. Returns those figures and the last image."""
import time


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
