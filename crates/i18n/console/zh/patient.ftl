# 处方表单中患者的训练站设置（方案的 [patient] 表）。

patient-legend = 患者的训练站
patient-intro = 这些设置随处方一起下发：训练站从下一次训练起使用。
patient-language-label = 训练站屏幕和语音的语言
patient-language-station = 按训练站上的选择
patient-side-legend = 忽略侧
patient-side-none = 无
patient-side-none-note = 屏幕按常规布局。
patient-side-left = 左侧
patient-side-left-note = 屏幕左侧不放重要内容。每项训练前，左边缘出现闪动的橙色条，并从左侧播放“请看这里”。
patient-side-right = 右侧
patient-side-right-note = 屏幕右侧不放重要内容。每项训练前，右边缘出现闪动的橙色条，并从右侧播放“请看这里”。
patient-speech-label = 朗读每页的主要句子
patient-volume-label = 语音音量，%
patient-countdown-label = 休息后，倒计时结束即开始下一项训练，秒
patient-countdown-wait = 等待患者
patient-saved-words = 训练站：{ $language }；忽略侧：{ $side ->
    [left] 左侧
    [right] 右侧
   *[none] 无
}；语音{ $speech ->
    [off] 关闭
   *[on] 开启，音量 { $volume }%
}；休息后：{ $countdown ->
    [count] { $seconds } 秒后开始下一项训练
   *[wait] 训练站等待患者
}。
