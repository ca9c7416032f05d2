#!/bin/bash
# The facing arm against its control (frozen, issue 57 item 4), as it was run on 2026-11-30:
#   run.sh CORE pets|tud
# CONTROL: /tmp/q/{pets,tud}{0,1,2}/bundle, compiled from main with `vc-compile SCENE --budget standard --seed S`
# (their renders beside them). The facing arm is each control bundle with a facing model trained on its own renders
# (attach.py); both arms are evaluated by vc-eval on the choosing and confirming halves, YOLO11n-pose @1280 the pose
# reference; then each facing bundle once more with the walk deciding wherever there is one (tracker_trust.py).
set -e
source .venv/bin/activate
export OMP_NUM_THREADS=1
core=$1; cam=$2
Y=../shared/baselines/yolo11n-pose-1280.onnx
if [ $cam = pets ]; then V=../shared/data/pets09_s2l1/vtest.avi; G=../shared/data/pets09_s2l1/gt_dev_frames_0001-0400.txt; H="1:200:5 201:400:5"; FPS="";
else V=../shared/data/tud_stadtmitte/frames; G=../shared/data/tud_stadtmitte/gt_world.txt; H="1:90:1 91:179:1"; FPS="--fps 25"; fi
E=experiments/2026-11-30-facing-from-the-crop
for s in 0 1 2; do
  PYTHONPATH=. taskset -c $core python $E/attach.py /tmp/q/$cam$s/bundle /tmp/q/$cam$s/renders $s /tmp/face/arm/$cam$s
  for h in $H; do
    for arm in control facing; do
      b=/tmp/q/$cam$s/bundle; [ $arm = facing ] && b=/tmp/face/arm/$cam$s
      taskset -c $core vc-eval $b --video $V --gt $G $FPS --frames $h --no-hog --external $Y --threads 1 --quiet \
          -o /tmp/face/eval/$arm/$cam$s/${h%%:*}
    done
    PYTHONPATH=. taskset -c $core python $E/tracker_trust.py /tmp/face/arm/$cam$s $V $G $h \
        /tmp/face/eval/facing_walk/$cam$s/${h%%:*} $FPS
  done
done
# then: PYTHONPATH=. python $E/summarise.py /tmp/face/eval
