# 处方表单（crates/hub/console/prescribe.js）。

prescribe-heading = 训练方案
prescribe-version = 第 { $version } 版，由 { $by } 于 { $when } 开具。
prescribe-version-gone = 已离开本机构的治疗师
prescribe-version-none = 尚未开具处方：训练站运行其默认训练。
prescribe-version-now = 第 { $version } 版，由 { $by } 刚刚开具。
prescribe-sessions-label = 每周训练次数
prescribe-assessment-label = 标准评估间隔天数（留空：不评估）
prescribe-trunk-cue-label = 躯干偏移超过 … 度时提醒坐直（留空：从不）
prescribe-no-exercise = 尚无训练项目：请添加一项。
prescribe-add-label = 添加训练项目
prescribe-add-button = 添加
prescribe-full = 一个方案最多 { $max } 项训练（每组计为一项）。
prescribe-message-note = 如需告知 { $name } 此次更改，请在下方消息框中填写，保存时随处方一起发送。
prescribe-save = 保存为新版本
prescribe-saving = 正在保存…
prescribe-saved = { $message ->
    [yes] 已保存为第 { $version } 版，并附上消息。
   *[no] 已保存为第 { $version } 版。
}
prescribe-message-problem = 消息：{ $problem }
prescribe-out-of-bounds = 有数值超出范围（范围见其旁）。
prescribe-too-many = 按组计共 { $count } 项训练：最多 { $max } 项。
prescribe-total = { $untimed ->
    [0] 约 { $minutes } 分钟训练，{ $rests } 分钟休息。
   *[other] 约 { $minutes } 分钟训练，{ $rests } 分钟休息，另有 { $untimed } 项训练未设分钟数（跑完一遍或由训练本身计时）。
}

prescribe-exercise-legend = 训练 { $n }：{ $name }
prescribe-kind-unknown = 本中心服务器不认识的训练类型：请在文本版中编辑。
prescribe-remove = 删除训练 { $n }
prescribe-levels-legend = 难度
prescribe-level-easy = 简单
prescribe-level-medium = 中等
prescribe-level-hard = 困难
prescribe-level-own = 自定义设置
prescribe-level-own-note = 已偏离预设级别（见详细设置）
prescribe-minutes-label = 分钟
prescribe-minutes-road = 沿道路跑完一遍
prescribe-sets-label = 组数（休息后重复该训练）
prescribe-rest-label = 每组后休息，秒
prescribe-rest-default = 仅显示简短提示卡
prescribe-dial-other = 目标的运动方式不是往返摆动：其设置在文本版中。
prescribe-dial-range-label = 方向盘每侧转动幅度，度
prescribe-dial-pace-label = 一次往返摆动，秒
prescribe-dial-words = 方向盘每侧最多转 { $degrees }°（{ $range ->
    [small] 小幅转动
    [quarter] 最多四分之一圈
   *[more] 超过四分之一圈
}），每 { $seconds } 秒往返一次（{ $pace ->
    [slow] 慢
    [moderate] 适中
   *[brisk] 快
}）。
prescribe-dial-sine = 目标：幅度 { $degrees }°、角频率 { $rate } rad/s 的正弦（amplitude_deg, frequency_rad_s）。
prescribe-ceiling-label = 方向盘最大推力（力矩上限），N·m（留空：采用训练站的设置）
prescribe-pedals-label = 由患者用踏板控制速度（需设分钟数；不勾选则自动控制速度）
prescribe-details-summary = 详细设置：级别背后的参数

prescribe-text-summary = 以文本编辑（全部设置，与训练站 regimens 文件夹中相同）
prescribe-text-label = 训练方案（TOML）
prescribe-text-save = 将文本保存为新版本

prescribe-bounds-heading = 训练站强制执行的安全限值
prescribe-bounds-ceiling = 力矩上限
prescribe-bounds-ceiling-text = 处方中最多 { $nm } N·m（{ $wheel ->
    [patient] 该患者方向盘所能提供的力矩
   *[consumer] 最强的民用方向盘
}），超出即拒绝。训练站随后再按自身方向盘的上限加以限制：处方只能降低患者的上限，不能提高。
prescribe-bounds-slew = 力矩变化
prescribe-bounds-slew-text = 无论处方如何，均由训练站的安全链限制变化速率。
prescribe-bounds-session = 单次训练
prescribe-bounds-session-text = 最多 { $max } 项训练（每组计为一项），计划总时长不超过 { $minutes } 分钟，含休息和训练之间的提示卡。
prescribe-bounds-levels = 级别
prescribe-bounds-levels-text = 每个简单、中等和困难级别都经训练站自身的校验程序检查。
prescribe-bounds-other = 其他所有设置
prescribe-bounds-other-text = 在其旁所示范围内。
prescribe-bounds-note = 表单中的范围来自训练方案的模式（schema），由中心服务器根据训练站自身的校验程序生成。中心服务器在保存前用该校验程序检查整个方案；训练站在下一次训练时采用新版本。

prescribe-difficulty-legend = 随患者调整的难度
prescribe-difficulty-adapt = 根据患者调整每次训练的难度（以目标成功率为准，并考虑“太简单”和“太难”的反馈）
prescribe-difficulty-changes = 调整：
prescribe-difficulty-note = 难度 1 即方案原样；0 为一半速度和幅度，并提供全部辅助。绝不超出处方；力矩上限始终不变。
prescribe-difficulty-target_success = 自适应调整的目标成功率
prescribe-difficulty-lowest = 允许的最低难度
prescribe-difficulty-highest = 允许的最高难度
prescribe-difficulty-start = 第一次训练的难度
prescribe-aspect-speed = 速度
prescribe-aspect-shape = 形状
prescribe-aspect-assist = 辅助

prescribe-kind-straight = 直路
prescribe-kind-sine = 正弦道路
prescribe-kind-triangle = 三角波道路
prescribe-kind-clothoid = 回旋曲线道路
prescribe-kind-sharp-turns = 急转弯
prescribe-kind-s-bend = S 形弯
prescribe-kind-lane-change = 变道
prescribe-kind-slalom = 绕桩
prescribe-kind-dial = 转盘
prescribe-kind-strength = 力量
prescribe-kind-haptic-sweep = 触觉扫描

prescribe-preset-straight-easy = 宽车道，慢速行驶。
prescribe-preset-straight-medium = 普通车道，城市车速。
prescribe-preset-straight-hard = 窄车道，较快行驶。
prescribe-preset-sine-easy = 宽车道中的平缓长波，慢速。
prescribe-preset-sine-medium = 论文中的弯曲道路。
prescribe-preset-sine-hard = 窄车道中更大更密的波浪。
prescribe-preset-triangle-easy = 浅之字形，转角宽，慢速。
prescribe-preset-triangle-medium = 转角圆滑的之字形。
prescribe-preset-triangle-hard = 陡之字形，转角急。
prescribe-preset-clothoid-easy = 略微收紧的弯道，慢速。
prescribe-preset-clothoid-medium = 逐渐收紧的弯道。
prescribe-preset-clothoid-hard = 窄车道中急剧收紧的弯道。
prescribe-preset-sharp-turns-easy = 几个大弧度的半圈转弯。
prescribe-preset-sharp-turns-medium = 左右直角转弯。
prescribe-preset-sharp-turns-hard = 更多直角转弯，更急更密。
prescribe-preset-s-bend-easy = 宽车道中的两个平缓弯道。
prescribe-preset-s-bend-medium = 先左后右的弯道。
prescribe-preset-s-bend-hard = 窄车道中的两个急弯。
prescribe-preset-lane-change-easy = 三次缓慢而长的变道。
prescribe-preset-lane-change-medium = 城市车速下的四次变道。
prescribe-preset-lane-change-hard = 六次快速变道。
prescribe-preset-slalom-easy = 六个相距较远的锥桶，慢速。
prescribe-preset-slalom-medium = 八个锥桶。
prescribe-preset-slalom-hard = 窄车道中十个紧密排列的锥桶。
prescribe-preset-dial-easy = 每侧小幅转动，慢速。
prescribe-preset-dial-medium = 每侧转动四分之一圈及以上。
prescribe-preset-dial-hard = 每侧大幅转动，较快。
prescribe-preset-strength-easy = 温和的测试：弹簧缓慢变硬。
prescribe-preset-strength-medium = 标准测试。
prescribe-preset-strength-hard = 较快的测试：弹簧更快变硬。
prescribe-preset-haptic-sweep-easy = 三个半分钟的阶段，小幅慢速摆动。
prescribe-preset-haptic-sweep-medium = 论文中的六个一分钟阶段。
prescribe-preset-haptic-sweep-hard = 六个一分钟阶段，摆动更快。

## 练习级别背后的设置（详细信息），每项对应处方中的一个字段：单位与处方一致。
prescribe-field-lane-width-m = 车道宽度，米
prescribe-field-length-m = 练习路段长度，米
prescribe-field-speed-m-s = 目标速度，米/秒
prescribe-field-amplitude-m = 弯道幅度，米
prescribe-field-periods = 完整波形的数量
prescribe-field-wavelength-m = 波长，米
prescribe-field-corner-radius-m = 圆角半径，米
prescribe-field-end-curvature-1-m = 终点曲率，1/米（正值：向左转）
prescribe-field-unwind-m = 回正弯道长度，米
prescribe-field-angle-deg = 转弯角度，°
prescribe-field-count = 转弯或变道次数
prescribe-field-radius-m = 转弯半径，米
prescribe-field-straight-m = 弯道之间的直道，米
prescribe-field-hold-m = 每次变道后的直道，米
prescribe-field-offset-m = 横向偏移，米
prescribe-field-transition-m = 一次变道的长度，米
prescribe-field-cone-count = 锥桶数量
prescribe-field-cone-spacing-m = 锥桶间距，米
prescribe-field-weave-m = 路线与每个锥桶的横向距离，米
prescribe-field-drift-deg = 目标向被忽略一侧移动的幅度，方向盘转角 °
prescribe-field-ramp-nm-per-s = 弹簧力矩上限升至最大值的速度，N·m/秒
prescribe-field-side-s = 每侧的时间上限，秒
prescribe-field-stiffness-nm-per-rad = 把方向盘保持在中间的弹簧刚度，N·m/rad
prescribe-field-amplitude-deg = 每侧摆动幅度，°
prescribe-field-frequency-rad-s = 摆动频率，rad/秒
prescribe-field-level-s = 每个级别的时间，秒
