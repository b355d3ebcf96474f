"""The streaming renderer's device pool plan (gpu/src/VulkanChunkBackend.cpp, planPool), mirrored
so that the bench can ask for a budget that holds a given number of chunk slots. The bench checks
the slot count the renderer reports (chunk_slots) rather than trusting this mirror."""
import re

GRANULE = 64 * 1024           # kAllocationGranule
RAY_BYTES, HIT_BYTES = 32, 48  # sizeof(StreamRayGpu), sizeof(StreamHitGpu)
MIN_RAYS, MAX_RAYS = 4096, 1 << 20  # kMinBatchRays, kMaxBatchRays
SLOT_ENTRY_BYTES = 88          # sizeof(ChunkSlot)


def granules(n):
    return (max(n, 1) + GRANULE - 1) // GRANULE * GRANULE


def batch_bytes(rays):
    return granules(rays * RAY_BYTES) + granules(rays * HIT_BYTES)


def table_bytes(slots):
    return granules(slots * SLOT_ENTRY_BYTES)


def parse_minimum_bytes(message):
    """The exact minimum from the renderer's 'below this scene's minimum of X = N bytes' error."""
    m = re.search(r"minimum of .*? = (\d+) bytes", message)
    return int(m.group(1)) if m else None


def slots_for(budget, slot_allocation, chunks):
    rays = min(max(budget // 4 // (RAY_BYTES + HIT_BYTES), MIN_RAYS), MAX_RAYS)
    while rays > MIN_RAYS and batch_bytes(rays) + slot_allocation + table_bytes(1) > budget:
        rays //= 2
    rays = max(rays, MIN_RAYS)
    available = budget - batch_bytes(rays)
    if available >= table_bytes(chunks) + slot_allocation:
        slots = (available - table_bytes(chunks)) // slot_allocation
    else:
        slots = 1
    return min(slots, chunks)


def budget_for_slots(minimum, chunks, slots):
    """Smallest budget (in 64 KiB steps above the scene's minimum) whose plan has `slots` slots."""
    slot_allocation = minimum - batch_bytes(MIN_RAYS) - table_bytes(1)
    budget = minimum
    while slots_for(budget, slot_allocation, chunks) < slots:
        budget += GRANULE
    return budget
