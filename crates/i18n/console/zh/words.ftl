# 指标、结束原因、练习类型、趋势和时间的临床用语。键、单位、小数位和范围只在
# crates/metrics/src/words.rs 中定义；这里只有名称。

## 指标名称

words-measure-active-s = 活动时间
words-measure-session-s = 训练时长
words-measure-paused-s = 暂停时间
words-measure-active-pct = 运动时间占比
words-measure-movements = 动作次数
words-measure-discrete-movements = 从静止到静止的动作
words-measure-movements-per-min = 每分钟动作次数
words-measure-reversals-per-min = 每分钟转向方向改变次数
words-measure-sparc-median = 流畅度（越接近 0 越流畅）
words-measure-ldlj-median = 加速度流畅度（越接近 0 越流畅）
words-measure-movement-peak-speed-deg-s-median = 单次动作最高转速
words-measure-movement-time-s-median = 单次动作时长
words-measure-speed-peaks-median = 单次动作中的停顿与重新启动
words-measure-speed-metric-median = 速度均匀度（1 为均匀）
words-measure-reaction-time-s-median = 反应时间
words-measure-anticipation-pct = 提前开始的变道
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
words-measure-trunk-cues = 坐直提醒次数
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

## 每项指标测量什么（供临床人员；words-definition-<key>；docs/MEASURES.md）

words-definition-active-s = 方向盘在转动的时间：各次动作时长之和，不含暂停。
words-definition-session-s = 从训练开始到结束的时间，含暂停。
words-definition-paused-s = 训练因患者暂停或休息而暂停的时间。
words-definition-active-pct = 练习时间中方向盘在转动的比例。
words-definition-movements = 方向盘的动作：速度高于本次训练最高速度的 5 %（至少 2.9 °/s），间隔不足 0.1 s 的合并，不足 0.2 s 的舍去。
words-definition-discrete-movements = 从静止到静止的动作：前后至少静止 0.2 s，最长 5 s。只有这些动作评估平稳度。
words-definition-movements-per-min = 每分钟练习的动作数：练习剂量。
words-definition-reversals-per-min = 每分钟练习中方向盘转向改变至少 2° 的次数。
words-definition-sparc-median = 方向盘速度的频谱弧长，取从静止到静止的动作的中位数；连续任务不计算。越接近 0 越平稳。
words-definition-ldlj-median = 方向盘速度的对数无量纲急动度，取从静止到静止的动作的中位数；连续任务不计算。越接近 0 越平稳。
words-definition-movement-peak-speed-deg-s-median = 一次动作中的最高转动速度，各动作的中位数。
words-definition-movement-time-s-median = 一次动作的时长，从速度超过阈值到回落，中位数。
words-definition-speed-peaks-median = 一次动作中的速度峰值个数（至少为其最高速度的 10 %），中位数；1 表示一次平稳的动作。
words-definition-speed-metric-median = 动作的平均速度除以最高速度，中位数；随恢复动作变得饱满而上升。
words-definition-reaction-time-s-median = 从目标不可预测的跳变（表盘的）到方向盘开始转动的时间，中位数。
words-definition-anticipation-pct = 提前可见的变道中，转动在变道后不到 0.1 s 就开始的比例：是预判，不是反应。
words-definition-initial-direction-error-deg-mean = 目标跳变后动作是否朝错误方向开始：0° 方向正确，180° 方向错误，平均值。
words-definition-reaction-time-left-s-median = 对目标向左不可预测跳变的反应时间，中位数。
words-definition-reaction-time-right-s-median = 对目标向右不可预测跳变的反应时间，中位数。
words-definition-initial-direction-error-left-deg-mean = 朝左侧目标时的错误方向起步，平均值（0° 正确，180° 错误）。
words-definition-initial-direction-error-right-deg-mean = 朝右侧目标时的错误方向起步，平均值（0° 正确，180° 错误）。
words-definition-path-length-ratio-median = 目标跳变后实际转动量除以到达目标所需转动量，中位数；1 表示直接到达。
words-definition-wheel-rom-deg = 练习中方向盘最大角度减最小角度。
words-definition-shoulder-elevation-rom-deg = 手臂传感器跟踪期间肩部抬高角度的最大值减最小值。
words-definition-elbow-flexion-rom-deg = 手臂传感器跟踪期间肘部弯曲角度的最大值减最小值。
words-definition-trunk-flexion-max-deg = 胸骨传感器测得的躯干相对起始姿势的最大前屈。
words-definition-trunk-flexion-mean-deg = 胸骨传感器测得的躯干相对起始姿势的平均前屈。
words-definition-trunk-lean-max-deg = 胸骨传感器测得的躯干相对起始姿势的最大侧倾。
words-definition-trunk-lean-mean-deg = 胸骨传感器测得的躯干相对起始姿势的平均侧倾。
words-definition-trunk-rotation-max-deg = 胸骨传感器测得的躯干相对起始姿势的最大扭转。
words-definition-trunk-rotation-mean-deg = 胸骨传感器测得的躯干相对起始姿势的平均扭转。
words-definition-trunk-beyond-pct = 任一躯干角度超过本站阈值的练习时间比例。
words-definition-trunk-compensated-movements-pct = 躯干超过阈值的方向盘动作所占比例。
words-definition-trunk-cues = 训练站提醒患者坐直的次数：躯干超出治疗师设定的提醒阈值并持续一秒；每 20 秒最多一次。
words-definition-pct-in-lane = 驾驶时间中汽车在本车道内的比例。
words-definition-rms-lateral-m = 汽车到车道中心距离的均方根。
words-definition-heading-rms-error-deg = 汽车行驶方向与道路方向夹角的均方根。
words-definition-cone-hits = 汽车碰到的锥桶数。
words-definition-completion-time-s = 到达路线终点所用的时间。
words-definition-tracking-rms-error-deg = 要求的方向盘角度与实际角度之差的均方根。
words-definition-dial-rms-error-deg = 表盘目标角度与方向盘指针之差的均方根。
words-definition-dial-mean-abs-error-deg = 表盘目标角度与方向盘指针之差的绝对值平均。
words-definition-strength-peak-left-nm = 方向盘几乎静止时向左对抗弹簧的最大扭矩。
words-definition-strength-sustained-left-nm = 向左保持至少 1 s 的最大扭矩。
words-definition-strength-peak-right-nm = 方向盘几乎静止时向右对抗弹簧的最大扭矩。
words-definition-strength-sustained-right-nm = 向右保持至少 1 s 的最大扭矩。
words-definition-assist-level-mean = 方向盘给予的帮助，练习中的平均值：0 无帮助，1 完全帮助。
words-definition-patient-work-pct = 患者在方向盘机械功中所占比例（患者与方向盘帮助之和）。
