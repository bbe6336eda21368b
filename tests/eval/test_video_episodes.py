"""``--video DIR --video-episodes N``: pictures of the first N episodes of each split (first
seed); every other episode plays batched, and the records are those of a run without video."""

from objsearch.eval.runner import EvalConfig, evaluate


def test_only_the_first_episodes_of_each_split_get_videos_and_the_records_do_not_change(tmp_path, cache_dir):
    config = EvalConfig(agent="oracle", suite="house-single", seeds=(5, 1), suite_config={"cache_dir": cache_dir})
    plain = evaluate(config, progress=False, batch=8)
    filmed = evaluate(config, progress=False, batch=8, video_dir=str(tmp_path), video_episodes=2)
    assert filmed == plain
    names = {p.name for p in tmp_path.iterdir()}
    assert names == {
        f"{split}_seed5_ep{i:04d}.{ext}"
        for split in ("seen-goals", "unseen-goals")
        for i in (0, 1)
        for ext in ("png", "mp4")
    }
