# 指标、结束原因、练习类型、趋势和时间的临床用语。键、单位、小数位和范围只在
# crates/metrics/src/words.rs 中定义；这里只有名称。

## 指标名称

words-measure-active-s = 活动时间
words-measure-session-s = 训练时长
words-measure-paused-s = 暂停时间
words-measure-active-pct = 运动时间占比
words-measure-movements = 动作次数
words-measure-movements-per-min = 每分钟动作次数
words-measure-reversals-per-min = 每分钟转向方向改变次数
words-measure-sparc-median = 流畅度（越接近 0 越流畅）
words-measure-ldlj-median = 加速度流畅度（越接近 0 越流畅）
words-measure-movement-peak-speed-deg-s-median = 单次动作最高转速
words-measure-movement-time-s-median = 单次动作时长
words-measure-speed-peaks-median = 单次动作中的停顿与重新启动
words-measure-speed-metric-median = 速度均匀度（1 为均匀）
words-measure-reaction-time-s-median = 反应时间
words-measure-initial-direction-error-deg-mean = 动作起始方向错误
words-measure-reaction-time-left-s-median = 反应时间，左侧目标
words-measure-reaction-time-right-s-median = 反应时间，右侧目标
words-measure-initial-direction-error-left-deg-mean = 起始方向错误，左侧目标
words-measure-initial-direction-error-right-deg-mean = 起始方向错误，右侧目标
words-measure-path-length-ratio-median = 超出所需的转动（1 为没有）
words-measure-wheel-rom-deg = 方向盘转动范围
words-measure-shoulder-elevation-rom-deg = 肩部抬举范围
words-measure-elbow-flexion-rom-deg = 肘部屈曲范围
words-measure-trunk-flexion-max-deg = 躯干前屈，最大
words-measure-trunk-flexion-mean-deg = 躯干前屈，平均
words-measure-trunk-lean-max-deg = 躯干侧倾，最大
words-measure-trunk-lean-mean-deg = 躯干侧倾，平均
words-measure-trunk-rotation-max-deg = 躯干旋转，最大
words-measure-trunk-rotation-mean-deg = 躯干旋转，平均
words-measure-trunk-beyond-pct = 躯干移动过多的时间
words-measure-trunk-compensated-movements-pct = 借助躯干完成的转动
words-measure-pct-in-lane = 车道内时间
words-measure-rms-lateral-m = 与车道中心的距离
words-measure-heading-rms-error-deg = 偏离道路方向
words-measure-cone-hits = 撞到的锥桶
words-measure-completion-time-s = 完成时间
words-measure-tracking-rms-error-deg = 与目标角度的距离
words-measure-dial-rms-error-deg = 表盘：与目标角度的距离
words-measure-dial-mean-abs-error-deg = 表盘：与目标角度的平均距离
words-measure-strength-peak-left-nm = 向左转的力量，峰值
words-measure-strength-sustained-left-nm = 向左转的力量，保持 1 秒
words-measure-strength-peak-right-nm = 向右转的力量，峰值
words-measure-strength-sustained-right-nm = 向右转的力量，保持 1 秒
words-measure-assist-level-mean = 方向盘的辅助（0 无，1 完全）
words-measure-patient-work-pct = 患者完成的工作占比
words-name-unit = { $name }（{ $unit }）

## 训练如何结束

words-end-complete = 已完成
words-end-stopped-by-patient = 患者提前结束
words-end-paused-too-long = 提前结束：暂停时间过长
words-end-screen-failed = 提前结束：屏幕故障
words-end-wheel-unplugged = 提前结束：方向盘已断开
words-end-arm-sensor-unplugged = 提前结束：手臂传感器已断开
words-end-safety-stop = 提前结束：安全停止（方向盘的力已关闭）
words-end-running = 仍在进行
words-end-unreported = 已结束；未报告结束方式
words-end-other = 提前结束
words-end-recording-stopped = { $end }；录制提前停止
words-not-in-trends = （不计入趋势）

## 练习类型

words-kind-road = 道路
words-kind-dial = 表盘
words-kind-strength = 力量测试
words-kind-haptic-sweep = 触觉扫描
words-kind-regimen = 训练方案
words-kinds-and = { $first }和{ $last }
words-regimen = 包含 { $count } 项练习的训练方案

## 趋势、时间、训练站

words-trend-better = 改善
words-trend-worse = 变差
words-trend-steady = 稳定
words-seconds = { $n } 秒
words-minutes = { $n } 分钟
words-of-prescribed = 处方 { $prescribed } 中完成 { $done }
words-station-paired = 训练站于 { $day } 配对

## 按简称（处方中的）列出的练习，以及一次训练中按顺序的练习

words-exercise-straight-road = 直路
words-exercise-sine-road = 正弦道路
words-exercise-triangle-road = 三角波道路
words-exercise-clothoid-road = 回旋曲线道路
words-exercise-sharp-turns = 急转弯
words-exercise-s-bend = S 形弯
words-exercise-lane-change = 变道
words-exercise-slalom = 绕桩
words-exercise-dial-sine = 指针：正弦
words-exercise-dial-multi-sine = 指针：多正弦
words-exercise-dial-step = 指针：阶跃
words-exercise-dial-ramp = 指针：斜坡
words-exercise-dial-chirp = 指针：扫频
words-exercise-strength = 力量
words-exercise-haptic-sweep = 触觉扫描
words-exercises-then = { $first }，然后{ $next }
