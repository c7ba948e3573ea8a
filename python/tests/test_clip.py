"""BVH clips from Python: Clip.load / parse / write, frames as numpy arrays, the rig of a
clip and its source skeleton, a frame as a pose and poses back as a clip (every channel as it
was), and physik.follow, which gives what `physik follow --bvh` writes."""
import json
import os
import warnings

import numpy
import pytest

import physik
from conftest import cli

# a CMU-like clip: Spine1 and LeftHand have their children at their own origin (no bone of their
# own), HeadTop has no child, Head's position channels stretch its bone; angles on either branch
CLIP = """HIERARCHY
ROOT Hips
{
  OFFSET 0 17 0
  CHANNELS 6 Xposition Yposition Zposition Zrotation Yrotation Xrotation
  JOINT LHipJoint
  {
    OFFSET 0 0 0
    CHANNELS 3 Zrotation Yrotation Xrotation
    JOINT LeftUpLeg
    {
      OFFSET 1.4 -1.8 0.8
      CHANNELS 3 Zrotation Yrotation Xrotation
      End Site
      {
        OFFSET 0 -14 0
      }
    }
  }
  JOINT LowerBack
  {
    OFFSET 0 0 0
    CHANNELS 3 Zrotation Yrotation Xrotation
    JOINT Spine1
    {
      OFFSET 0 4 0
      CHANNELS 3 Zrotation Yrotation Xrotation
      JOINT Neck
      {
        OFFSET 0 0 0
        CHANNELS 3 Zrotation Yrotation Xrotation
        JOINT Head
        {
          OFFSET 0 1.6 0
          CHANNELS 6 Xposition Yposition Zposition Zrotation Yrotation Xrotation
          JOINT HeadTop
          {
            OFFSET 0 1.8 0
            CHANNELS 3 Zrotation Yrotation Xrotation
          }
        }
      }
      JOINT LeftShoulder
      {
        OFFSET 0 0 0
        CHANNELS 3 Zrotation Yrotation Xrotation
        JOINT LeftHand
        {
          OFFSET 8 0 0
          CHANNELS 3 Zrotation Yrotation Xrotation
          JOINT LThumb
          {
            OFFSET 0 0 0
            CHANNELS 3 Zrotation Yrotation Xrotation
            End Site
            {
              OFFSET 0.6 0 0.6
            }
          }
          JOINT LeftFingerBase
          {
            OFFSET 0 0 0
            CHANNELS 3 Zrotation Yrotation Xrotation
            End Site
            {
              OFFSET 1.2 0 0
            }
          }
        }
      }
    }
  }
}
MOTION
Frames: %d
Frame Time: 0.0083333
%s
"""


def make_clip(nframe=6, seed=5):
    rng = numpy.random.default_rng(seed)
    rows = []
    for f in range(nframe):
        row = [rng.uniform(-3, 3), 17 + rng.uniform(-1, 1), rng.uniform(-3, 3)]
        row += list(rng.uniform(-180, 180, 3))           # Hips
        for _ in range(5):                                 # LHipJoint .. Neck
            row += list(rng.uniform(-180, 180, 3))
        row += [rng.uniform(-0.1, 0.1), 1.6 + rng.uniform(-0.1, 0.1), rng.uniform(-0.1, 0.1)]
        for _ in range(6):                                 # Head's rotation .. LeftFingerBase
            row += list(rng.uniform(-180, 180, 3))
        rows.append(" ".join("%.12g" % v for v in row))
    return physik.Clip.parse(CLIP % (nframe, "\n".join(rows)), "cmu.bvh")


def test_clip_arrays_read_and_write(tmp_path):
    clip = make_clip()
    assert clip.nframe == 6 and clip.frames.shape == (6, clip.nchannel) == (6, 42)
    assert clip.joint_names[:3] == ["Hips", "LHipJoint", "LeftUpLeg"]
    assert clip.joint_parents[:3] == [-1, 0, 1]
    assert clip.columns[0] == "Hips:Xposition" and clip.channels[1] == [
        "Zrotation", "Yrotation", "Xrotation"]
    assert clip.offsets.shape == (12, 3) and clip.end_sites[2].shape == (1, 3)
    frames = clip.frames
    frames[:, 3] += 10.0
    clip.frames = frames
    path = tmp_path / "out" / "clip.bvh"
    clip.write(str(path))
    back = physik.Clip.load(str(path))
    assert numpy.abs(back.frames - clip.frames).max() < 1e-9
    assert back.frame_time == pytest.approx(0.0083333)


def test_clip_frames_are_checked():
    clip = make_clip()
    with pytest.raises(physik.InputError, match="shape"):
        clip.frames = numpy.zeros((2, 5))
    bad = clip.frames
    bad[1, 4] = numpy.nan
    with pytest.raises(physik.InputError, match="frame 1"):
        clip.frames = bad
    far = clip.frames
    far[0, 0] = 2e9
    with pytest.raises(physik.InputError, match="1e9"):
        clip.frames = far
    with pytest.raises(physik.InputError, match="frame_time"):
        clip.frame_time = 0.0
    with pytest.raises(physik.InputError):
        physik.Clip.parse("HIERARCHY\nROOT A\n{\n", "bad.bvh")


def test_rig_of_a_clip_keeps_its_skeleton():
    clip = make_clip()
    rig = physik.Rig.from_bvh(clip, scale=0.056)
    s = rig.source_skeleton
    assert [j["name"] for j in s["joints"]] == clip.joint_names
    assert s["scale"] == 0.056 and s["frame_time"] == pytest.approx(0.0083333)
    assert "bones" not in s["joints"][clip.joint_names.index("Spine1")]  # no bone of its own
    assert any("Spine1" in n and "no bone of its own" in n for n in rig.source_notes)
    assert rig.root == "free"
    assert physik.Rig.chain(3).source_skeleton is None
    with pytest.raises(physik.InputError, match="axes"):
        physik.Rig.from_bvh(clip, axes="x-up")


def test_every_channel_comes_back():
    clip = make_clip()
    rig = physik.Rig.from_bvh(clip, scale=0.056)
    poses = [clip.pose(rig, f) for f in range(clip.nframe)]
    back = physik.Clip.of_poses(rig, poses, clip.frame_time, source=clip)
    assert back.joint_names == clip.joint_names and back.channels == clip.channels
    assert numpy.abs(back.frames - clip.frames).max() < 1e-6
    # without the source frames the positions are still the rig's: the joints' world positions
    # agree with a clip written with them
    plain = physik.Clip.of_poses(rig, poses, clip.frame_time)
    assert plain.nframe == clip.nframe
    q = physik.Clip.of_poses(rig, poses, clip.frame_time, source=clip, quaternion=True)
    assert q.channels[1] == ["Wquaternion", "Xquaternion", "Yquaternion", "Zquaternion"]


def test_a_pose_of_another_skeleton_is_refused():
    rig = physik.Rig.load(os.path.join(os.path.dirname(__file__), "..", "..", "models", "rigs",
                                       "pinhead.json"))
    with pytest.raises(physik.InputError, match="source skeleton"):
        make_clip().pose(rig, 0)
    other = physik.Rig.from_bvh(make_clip(), scale=0.056)
    with pytest.raises(physik.InputError, match="outside"):
        make_clip().pose(other, 99)


def test_follow_is_the_clis_follow(tmp_path):
    clip = make_clip(nframe=4)
    rig = physik.Rig.from_bvh(clip, scale=0.056)
    run = physik.follow(clip, rig, ground=None, params={"dt": 0.0083333 / 2})
    assert isinstance(run, physik.FollowRun)
    assert run.clip.joint_names == clip.joint_names
    assert run.clip.nframe == clip.nframe  # one frame per clip frame, as --bvh writes
    clip_path, rig_path = tmp_path / "c.bvh", tmp_path / "r.json"
    clip.write(str(clip_path))
    with open(rig_path, "w") as f:
        json.dump(rig.to_dict(), f)
    status, _, err = cli("follow", clip_path, "--rig", rig_path, "--out", tmp_path / "run",
                         "--no-ground", "--set", "dt=%r" % (0.0083333 / 2), "--bvh",
                         tmp_path / "f.bvh", "--quiet")
    assert status == 0, err
    # the CLI reads the rig from its file, whose numbers differ from the converted rig's in the
    # last bits (rest frames and masses written and read back): the same run is the one of the
    # same file
    run = physik.follow(clip, physik.Rig.load(str(rig_path)), ground=None,
                        params={"dt": 0.0083333 / 2})
    cli_clip = physik.Clip.load(str(tmp_path / "f.bvh"))
    assert numpy.abs(cli_clip.frames - run.clip.frames).max() < 1e-9
    summary = json.load(open(tmp_path / "run" / "summary.json"))
    assert summary["final_state_hash"] == run.summary["final_state_hash"]


def test_write_back_warns_what_the_file_cannot_hold():
    clip = physik.Clip.parse("""HIERARCHY
ROOT A
{
  OFFSET 0 0 0
  CHANNELS 1 Zrotation
  End Site
  {
    OFFSET 0 10 0
  }
}
MOTION
Frames: 1
Frame Time: 0.1
30
""")
    rig = physik.Rig.from_bvh(clip, scale=0.1)
    assert rig.root == "pinned"
    pose = clip.pose(rig, 0)
    turned = numpy.array(pose.local_rotations)
    turned[0] = [0.0, numpy.sin(0.3), 0.0, numpy.cos(0.3)]  # about the bone: no channel holds it
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        physik.Clip.of_poses(rig, [(turned, pose.root_head)], 0.1)
    assert any(issubclass(w.category, physik.WriteBackWarning) and "rotation channels" in
               str(w.message) for w in caught)
