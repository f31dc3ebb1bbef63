# A 3-D picture of each robot of the study (issue 19; point masses too): frame box, pulleys with their swivel
# axes, platform and cables at the study's orientation, and the RW_C box of the DOE robot.


rule robot_view:
    input:
        robot=lambda w: ROBOTS[w.robot],
        box=LAYOUT.path("regular_workspace", "json"),
    output:
        **outputs("robot_view", figure=("../report/robot_view.rst", "Robot")),
    params:
        **COMMON,
        study=uses("robots", "dead_length_m", "rotvec_rad", "doe", "redundancy"),
    log:
        LAYOUT.log("robot_view"),
    shell:
        "{params.cdpr} job robot-view --study {params.study_file:q} --robot-key {wildcards.robot}"
        " --box-file {input.box:q} --figure {output.figure:q}" + TO_LOG
